#include "world/gen/terrain.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <vector>

#include "world/base/assert.h"
#include "world/gen/noise.h"
#include "world/lod/cell_vote.h"

namespace vx::world {

namespace {

constexpr int kGrid = 4;             // Spacing of the sparse noise samples, blocks.
constexpr int kCells = kChunkSize / kGrid; // 8 lattice cells per chunk edge, 9 samples.

// Salts that give each noise field its own seed.
constexpr uint64_t kSaltHills = 0x48494C4Cull;
constexpr uint64_t kSaltMountain = 0x4D4F554Eull;
constexpr uint64_t kSaltRidge = 0x52494447ull;
constexpr uint64_t kSaltCave = 0x43415645ull;
constexpr uint64_t kSaltSnow = 0x534E4F57ull;
constexpr uint64_t kSaltCrystal = 0x43525953ull;
constexpr uint64_t kSaltLamp = 0x4C414D50ull;

inline float lerp(float a, float b, float t) { return a + t * (b - a); }
inline float smoothstep(float a, float b, float x) {
    const float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}
// The one bilinear form used for heights, so generate() and surface_height() agree bit for bit.
inline int bilerp_floor(float h00, float h10, float h01, float h11, int fx, int fz) {
    const float tx = float(fx) * (1.0f / kGrid), tz = float(fz) * (1.0f / kGrid);
    return int(std::floor(lerp(lerp(h00, h10, tx), lerp(h01, h11, tx), tz)));
}
inline int64_t floor_grid(int64_t v) { return v & ~int64_t(kGrid - 1); }

// Bounds of the height field over all columns (each noise is within about [-1, 1]; 2 blocks of
// margin): far above or deep below needs no noise at all.
int64_t height_hi(const TerrainParams& p) {
    return int64_t(p.base_height + p.hill_amplitude + p.mountain_amplitude) + 2;
}
int64_t height_lo(const TerrainParams& p) { return int64_t(float(p.base_height) - p.hill_amplitude) - 2; }

BlockId must_find(const char* name) {
    const auto id = BlockRegistry::default_registry().find(name);
    VX_ASSERT_MSG(id.has_value(), name);
    return *id;
}

} // namespace

// Per-column data of one chunk, indexed [z][x] in local coordinates.
struct TerrainGenerator::Columns {
    int h[kChunkSize][kChunkSize];           // Surface height, world y.
    int carve_limit[kChunkSize][kChunkSize]; // Highest world y caves may carve.
    BlockId top[kChunkSize][kChunkSize];     // Surface block.
    BlockId under[kChunkSize][kChunkSize];   // The soil_depth blocks below it.
    int row_hmin[kChunkSize], row_hmax[kChunkSize]; // Height range of each z row.
    int row_carve_max[kChunkSize];                  // Highest carve limit of each z row.
    float grid[kCells + 1][kCells + 1]; // Heights every kGrid blocks, [k][i] for z, x.
    int grid_hmin, grid_hmax;           // Bounds of h over the chunk.
};

// The cave field c = a² + b² sampled every kGrid blocks: x, z at origin + 4i (i = 0..8) and
// y at y0 - 4 + 4j (j = 0..9), then interpolated in y for local y = -1..32 (one row beyond the
// chunk on each side, for the floor and ceiling tests of lamps and crystals at its borders).
struct TerrainGenerator::Caves {
    float lattice[kCells + 1][kCells + 2][kCells + 1]; // [k][j][i]
    float rows[kCells + 1][kChunkSize + 2][kCells + 1]; // [k][y + 1][i]
    float thr[kChunkSize + 2];                          // Threshold per local y + 1.
    bool solid_below[kChunkSize][kChunkSize];           // Terrain-solid at local y = -1, [z][x].
    bool solid_above[kChunkSize][kChunkSize];           // ... at local y = 32.
};

TerrainGenerator::TerrainGenerator(uint64_t seed, TerrainParams params) : m_seed(seed), m_params(params) {
    m_ids = {must_find("stone"), must_find("dirt"),  must_find("grass"),  must_find("sand"), must_find("water"),
             must_find("snow"),  must_find("glass"), must_find("mirror"), must_find("lamp")};
    for (BlockId id : {m_ids.stone, m_ids.dirt, m_ids.grass, m_ids.sand, m_ids.snow}) {
        VX_ASSERT(id < 32);
        m_terrain_mask |= 1u << id;
    }
}

// Height at a grid column (x, z multiples of kGrid): lowland hills plus mountains where a
// low-frequency mask allows them, with ridged noise (1 - |n|) for sharp crests.
float TerrainGenerator::coarse_height(int64_t x, int64_t z) const {
    const TerrainParams& p = m_params;
    // Wavelengths 256..16 (sampled every 4 blocks, so no octave is finer than 4 samples).
    const float hills = noise::fbm_2d_at(m_seed ^ kSaltHills, x, z, 8, 5, 0.5f);
    const float mask = smoothstep(0.05f, 0.45f, noise::fbm_2d_at(m_seed ^ kSaltMountain, x, z, 10, 2, 0.5f));
    float h = float(p.base_height) + p.hill_amplitude * hills;
    if (mask > 0.0f) {
        const float ridge = 1.0f - std::abs(noise::gradient_2d_at(m_seed ^ kSaltRidge, x, z, 7));
        h += p.mountain_amplitude * mask * (0.3f + 0.7f * ridge * ridge);
    }
    return h;
}

int TerrainGenerator::surface_height(int64_t x, int64_t z) const {
    const int64_t gx = floor_grid(x), gz = floor_grid(z);
    return bilerp_floor(coarse_height(gx, gz), coarse_height(gx + kGrid, gz), coarse_height(gx, gz + kGrid),
                        coarse_height(gx + kGrid, gz + kGrid), int(x - gx), int(z - gz));
}

int64_t TerrainGenerator::height_min() const { return height_lo(m_params); }
int64_t TerrainGenerator::height_max() const { return height_hi(m_params); }

// Heights on the chunk's 9 x 9 grid, and integer bounds of every column height (bilinear
// interpolation stays within its samples).
void TerrainGenerator::fill_grid(ChunkCoord c, Columns& cols) const {
    const BlockPos o = chunk_origin(c);
    float lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k <= kCells; ++k)
        for (int i = 0; i <= kCells; ++i) {
            const float h = coarse_height(o.x + kGrid * i, o.z + kGrid * k);
            cols.grid[k][i] = h;
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
    cols.grid_hmin = int(std::floor(lo));
    cols.grid_hmax = int(std::floor(hi));
}

// Beaches and sea floors are sand; high peaks are snow (the line jittered by -4..4 per column)
// over bare rock; grass over dirt elsewhere.
TerrainGenerator::SurfaceIds TerrainGenerator::surface_ids(int h, int64_t x, int64_t z) const {
    const TerrainParams& p = m_params;
    if (h <= p.sea_level + 1)
        return {m_ids.sand, m_ids.sand};
    // The jitter only matters within 4 blocks of the line: hash there alone.
    const bool snow = h >= p.snow_line + 4 ||
                      (h >= p.snow_line - 4 &&
                       h >= p.snow_line + int(noise::hash_coords(m_seed ^ kSaltSnow, x, z) % 9) - 4);
    return snow ? SurfaceIds{m_ids.snow, m_ids.stone} : SurfaceIds{m_ids.grass, m_ids.dirt};
}

void TerrainGenerator::fill_columns(ChunkCoord c, Columns& cols) const {
    const BlockPos o = chunk_origin(c);
    const auto& grid = cols.grid;
    const TerrainParams& p = m_params;
    for (int z = 0; z < kChunkSize; ++z) {
        const int k = z / kGrid;
        for (int x = 0; x < kChunkSize; ++x) {
            const int i = x / kGrid;
            const int h = bilerp_floor(grid[k][i], grid[k][i + 1], grid[k + 1][i], grid[k + 1][i + 1], x % kGrid, z % kGrid);
            cols.h[z][x] = h;
            const SurfaceIds ids = surface_ids(h, o.x + x, o.z + z);
            cols.top[z][x] = ids.top;
            cols.under[z][x] = ids.under;
            // Keep a roof over caves near and under the sea so they do not open into the water.
            cols.carve_limit[z][x] = std::min(p.cave_top, h > p.sea_level + 3 ? h : h - 6);
        }
        cols.row_hmin[z] = *std::min_element(cols.h[z], cols.h[z] + kChunkSize);
        cols.row_hmax[z] = *std::max_element(cols.h[z], cols.h[z] + kChunkSize);
        cols.row_carve_max[z] = *std::max_element(cols.carve_limit[z], cols.carve_limit[z] + kChunkSize);
    }
}

// Tunnels fade out over the 24 blocks above cave_bottom.
float TerrainGenerator::cave_threshold(int64_t y) const {
    const float r = m_params.cave_radius;
    const float taper = std::clamp(float(y - m_params.cave_bottom) * (1.0f / 24.0f), 0.0f, 1.0f);
    return r * r * taper;
}

// Samples the cave lattice; false when no block of the chunk can be carved (the interpolated
// field is never below the smallest sample, so min(samples) >= max(threshold) rules caves out).
bool TerrainGenerator::fill_caves(ChunkCoord c, int top_y, Caves& cv) const {
    const BlockPos o = chunk_origin(c);
    float thr_max = 0.0f;
    for (int y = -1; y <= kChunkSize; ++y) {
        cv.thr[y + 1] = cave_threshold(o.y + y);
        if (y >= 0 && y < kChunkSize && o.y + y <= top_y)
            thr_max = std::max(thr_max, cv.thr[y + 1]);
    }
    if (thr_max <= 0.0f)
        return false;
    noise::Noise3Pair n[kCells + 1][kCells + 2][kCells + 1];
    noise::gradient_3d_pair_grid(m_seed ^ kSaltCave, o.x, o.y - kGrid, o.z, kGrid, kCells + 1, kCells + 2, kCells + 1, 6, 6,
                                 &n[0][0][0]);
    float lo = INFINITY;
    for (int k = 0; k <= kCells; ++k)
        for (int j = 0; j <= kCells + 1; ++j)
            for (int i = 0; i <= kCells; ++i) {
                const float v = n[k][j][i].a * n[k][j][i].a + n[k][j][i].b * n[k][j][i].b;
                cv.lattice[k][j][i] = v;
                if (j >= 1)
                    lo = std::min(lo, v);
            }
    if (lo >= thr_max)
        return false;
    for (int k = 0; k <= kCells; ++k)
        for (int y = -1; y <= kChunkSize; ++y) {
            const int j = (y + kGrid) / kGrid; // Sample at or below y (y0 - 4 is j = 0).
            const float t = float((y + kGrid) % kGrid) * (1.0f / kGrid);
            for (int i = 0; i <= kCells; ++i)
                cv.rows[k][y + 1][i] = j > kCells ? cv.lattice[k][j][i] : lerp(cv.lattice[k][j][i], cv.lattice[k][j + 1][i], t);
        }
    return true;
}

namespace {

// Cave field at local (x, z) from one y row of Caves::rows: z first, then x, in the same order
// everywhere (the fill loop and the border rows must agree bit for bit).
template <class Rows> inline float row_value(const Rows& rows, int x, int ry, int z) {
    const int k = z / kGrid, i = x / kGrid;
    const float tz = float(z % kGrid) * (1.0f / kGrid), tx = float(x % kGrid) * (1.0f / kGrid);
    return lerp(lerp(rows[k][ry][i], rows[k + 1][ry][i], tz), lerp(rows[k][ry][i + 1], rows[k + 1][ry][i + 1], tz), tx);
}

} // namespace

// Terrain blocks (what the surface and soil are made of), as opposed to air, water and features.
bool TerrainGenerator::is_terrain_solid(BlockId id) const { return id < 32 && ((m_terrain_mask >> id) & 1u); }

// Terrain-solid (not air, water or carved) at local (x, y, z) of a column, any y.
bool TerrainGenerator::solid_at(const Columns& cols, const Caves& cv, int64_t y0, int x, int y, int z) const {
    const int64_t wy = y0 + y;
    if (wy > cols.h[z][x])
        return false;
    const float thr = cv.thr[y + 1];
    if (thr <= 0.0f || wy > cols.carve_limit[z][x])
        return true;
    return row_value(cv.rows, x, y + 1, z) >= thr;
}

// Writes the blocks: terrain by height, carved tunnels, and lamps on tunnel floors (cave air over
// terrain, one in lamp_rarity by a position hash). Rows are visited in increasing y, so the block
// below is final terrain when a lamp is decided; at y = 0 the border row of `cv` stands in.
void TerrainGenerator::fill_blocks(ChunkCoord c, const Columns& cols, const Caves* cv, BlockId* ids) const {
    const TerrainParams& p = m_params;
    const BlockPos o = chunk_origin(c);
    for (int z = 0; z < kChunkSize; ++z) {
        const int k = z / kGrid;
        const float tz = float(z % kGrid) * (1.0f / kGrid);
        for (int y = 0; y < kChunkSize; ++y) {
            const int wy = int(o.y + y); // generate() only fills chunks near the height range.
            BlockId* out = ids + local_index(0, y, z);
            const BlockId above = wy <= p.sea_level ? m_ids.water : kAir;
            if (wy > cols.row_hmax[z]) {
                std::fill_n(out, kChunkSize, above);
                continue;
            }
            const float thr = cv ? cv->thr[y + 1] : 0.0f;
            const bool cave_row = thr > 0.0f && wy <= cols.row_carve_max[z];
            // Rows under every column's soil are plain stone before carving.
            if (wy < cols.row_hmin[z] - p.soil_depth) {
                std::fill_n(out, kChunkSize, m_ids.stone);
            } else {
                // Branch-free terrain by height (a branch per block mispredicts at the surface).
                for (int x = 0; x < kChunkSize; ++x) {
                    const int h = cols.h[z][x];
                    const BlockId soil = wy == h ? cols.top[z][x] : cols.under[z][x];
                    const BlockId ground = wy >= h - p.soil_depth ? soil : m_ids.stone;
                    out[x] = wy > h ? above : ground;
                }
            }
            if (!cave_row)
                continue;
            // Same expression as row_value(): z first, then x (the border rows must agree). The
            // interpolants stay within their samples, so a row whose samples all reach the
            // threshold has no tunnel. Carving is a bit mask: tunnel edges defeat branches.
            float v[kChunkSize];
            float row_min = INFINITY;
            for (int i = 0; i < kCells; ++i) {
                const float a = lerp(cv->rows[k][y + 1][i], cv->rows[k + 1][y + 1][i], tz);
                const float b = lerp(cv->rows[k][y + 1][i + 1], cv->rows[k + 1][y + 1][i + 1], tz);
                row_min = std::min(row_min, std::min(a, b));
                for (int t = 0; t < kGrid; ++t)
                    v[i * kGrid + t] = lerp(a, b, float(t) * (1.0f / kGrid));
            }
            if (row_min >= thr)
                continue;
            uint32_t carved = 0;
            for (int x = 0; x < kChunkSize; ++x)
                carved |= uint32_t((v[x] < thr) & (wy <= cols.carve_limit[z][x])) << x;
            while (carved) {
                const int x = std::countr_zero(carved);
                carved &= carved - 1;
                const bool floor = y == 0 ? cv->solid_below[z][x] : is_terrain_solid(out[x - kChunkSize]);
                out[x] = floor && noise::hash_coords(m_seed ^ kSaltLamp, o.x + x, wy, o.z + z) %
                                          uint64_t(p.lamp_rarity) == 0
                             ? m_ids.lamp
                             : kAir;
            }
        }
    }
}

// Crystal clusters: one candidate centre per (2^bits)^3 cell, kept with probability
// 1 / crystal_rarity; within its radius (4..7 blocks), cave air (air at or below the surface)
// touching a terrain floor or ceiling turns to glass (two thirds) or mirror. Only cave air changes, so
// cave-free chunks never hold crystals, and lamps stay.
void TerrainGenerator::place_crystals(ChunkCoord c, const Columns& cols, const Caves& cv, BlockId* ids) const {
    constexpr int kMaxRadius = 7;
    const int bits = m_params.crystal_cell_bits;
    const BlockPos o = chunk_origin(c);
    const BlockPos lo = (o - int64_t(kMaxRadius)) >> int64_t(bits);
    const BlockPos hi = (o + int64_t(kChunkSize - 1 + kMaxRadius)) >> int64_t(bits);
    for (int64_t cz = lo.z; cz <= hi.z; ++cz)
        for (int64_t cy = lo.y; cy <= hi.y; ++cy)
            for (int64_t cx = lo.x; cx <= hi.x; ++cx) {
                const uint64_t h = noise::hash_coords(m_seed ^ kSaltCrystal, cx, cy, cz);
                if (h % uint64_t(m_params.crystal_rarity) != 0)
                    continue;
                const int64_t mask = (int64_t(1) << bits) - 1;
                const BlockPos centre = BlockPos(cx, cy, cz) * (int64_t(1) << bits) +
                                        BlockPos(int64_t(h >> 16) & mask, int64_t(h >> 24) & mask, int64_t(h >> 32) & mask);
                const int64_t r = 4 + int64_t((h >> 40) % 4);
                const BlockPos a = glm::max(centre - r, o) - o;
                const BlockPos b = glm::min(centre + r, o + int64_t(kChunkSize - 1)) - o;
                for (int64_t z = a.z; z <= b.z; ++z)
                    for (int64_t y = a.y; y <= b.y; ++y)
                        for (int64_t x = a.x; x <= b.x; ++x) {
                            const BlockPos d = o + BlockPos(x, y, z) - centre;
                            const int idx = local_index(int(x), int(y), int(z));
                            if (d.x * d.x + d.y * d.y + d.z * d.z > r * r || ids[idx] != kAir ||
                                o.y + y > cols.h[z][x])
                                continue;
                            const bool floor = y == 0 ? cv.solid_below[z][x] : is_terrain_solid(ids[idx - kChunkSize]);
                            const bool ceiling = y == kChunkSize - 1 ? cv.solid_above[z][x]
                                                                     : is_terrain_solid(ids[idx + kChunkSize]);
                            if (!floor && !ceiling)
                                continue;
                            const uint64_t hb = noise::hash_coords(m_seed ^ kSaltCrystal ^ 1, o.x + x, o.y + y, o.z + z);
                            ids[idx] = hb % 3 == 0 ? m_ids.mirror : m_ids.glass;
                        }
            }
}

Chunk TerrainGenerator::generate(ChunkCoord c) const {
    const TerrainParams& p = m_params;
    const int64_t y0 = chunk_origin(c).y, y1 = y0 + kChunkSize - 1;
    const int64_t h_hi = height_hi(p), h_lo = height_lo(p);
    if (y0 > std::max<int64_t>(h_hi, p.sea_level))
        return Chunk(kAir);
    if (y1 < p.cave_bottom && y1 < h_lo - p.soil_depth)
        return Chunk(m_ids.stone);
    // Decide from the height bounds before computing any column (uniform chunks stop here).
    auto cols = std::make_unique<Columns>();
    fill_grid(c, *cols);
    if (y0 > std::max(cols->grid_hmax, p.sea_level))
        return Chunk(kAir);
    if (y0 > cols->grid_hmax && y1 <= p.sea_level)
        return Chunk(m_ids.water);
    auto cv = std::make_unique<Caves>();
    const int carve_top = std::min(cols->grid_hmax, p.cave_top);
    const bool caves = y1 >= p.cave_bottom && y0 <= carve_top && fill_caves(c, carve_top, *cv);
    if (!caves && y1 < cols->grid_hmin - p.soil_depth)
        return Chunk(m_ids.stone);
    fill_columns(c, *cols);
    if (caves)
        for (int z = 0; z < kChunkSize; ++z)
            for (int x = 0; x < kChunkSize; ++x) {
                cv->solid_below[z][x] = solid_at(*cols, *cv, y0, x, -1, z);
                cv->solid_above[z][x] = solid_at(*cols, *cv, y0, x, kChunkSize, z);
            }
    std::unique_ptr<BlockId[]> ids(new BlockId[kChunkVolume]);
    fill_blocks(c, *cols, caves ? cv.get() : nullptr, ids.get());
    if (caves)
        place_crystals(c, *cols, *cv, ids.get());
    return Chunk::from_dense(std::span<const BlockId>(ids.get(), kChunkVolume));
}

// ---- Levels of detail ----

// Height samples every kGrid blocks over a coarse chunk's footprint, as generate() takes them.
struct TerrainGenerator::CoarseGrid {
    BlockPos origin{0};       // Of the coarse chunk.
    int cell = 0;             // Cell edge, blocks.
    int n = 0;                // Samples per edge.
    std::vector<float> h;     // [k * n + i]: coarse_height(origin.x + kGrid * i, origin.z + kGrid * k).
    // Per block column of the cell column at hand, reused: exact height and surface ids.
    std::vector<int> col_h;
    std::vector<SurfaceIds> col_ids;
};

// One cell column (cx, cz) of a coarse chunk: 32 cells written to dense[local_index(cx, y, cz)].
void TerrainGenerator::coarse_column(CoarseGrid& g, int cx, int cz, BlockId* dense) const {
    const TerrainParams& p = m_params;
    const int s = g.cell;
    const int64_t y0 = g.origin.y, y1 = y0 + int64_t(kChunkSize) * s - 1;
    // Bounds from the samples the footprint interpolates between, one block of margin against
    // rounding: cell columns far from this chunk's y range need no per-column work.
    const int i0 = cx * s / kGrid, i1 = (cx * s + s - 1) / kGrid + 1;
    const int k0 = cz * s / kGrid, k1 = (cz * s + s - 1) / kGrid + 1;
    float lo = INFINITY, hi = -INFINITY;
    for (int k = k0; k <= k1; ++k)
        for (int i = i0; i <= i1; ++i) {
            lo = std::min(lo, g.h[size_t(k) * size_t(g.n) + size_t(i)]);
            hi = std::max(hi, g.h[size_t(k) * size_t(g.n) + size_t(i)]);
        }
    auto write_all = [&](BlockId id) {
        for (int y = 0; y < kChunkSize; ++y)
            dense[local_index(cx, y, cz)] = id;
    };
    if (y0 > std::max<int64_t>(int64_t(std::floor(hi)) + 1, p.sea_level))
        return write_all(kAir);
    if (y1 < int64_t(std::floor(lo)) - 1 - p.soil_depth)
        return write_all(m_ids.stone);
    // Exact column heights and surface ids, as fill_columns() computes them.
    int hmin = INT32_MAX, hmax = INT32_MIN;
    for (int dz = 0; dz < s; ++dz) {
        const int lz = cz * s + dz, k = lz / kGrid;
        for (int dx = 0; dx < s; ++dx) {
            const int lx = cx * s + dx, i = lx / kGrid;
            const float* r0 = &g.h[size_t(k) * size_t(g.n) + size_t(i)];
            const float* r1 = r0 + g.n;
            const int h = bilerp_floor(r0[0], r0[1], r1[0], r1[1], lx % kGrid, lz % kGrid);
            const size_t j = size_t(dz) * size_t(s) + size_t(dx);
            g.col_h[j] = h;
            g.col_ids[j] = surface_ids(h, g.origin.x + lx, g.origin.z + lz);
            hmin = std::min(hmin, h);
            hmax = std::max(hmax, h);
        }
    }
    for (int y = 0; y < kChunkSize; ++y) {
        const int64_t ylo = y0 + int64_t(y) * s, yhi = ylo + s - 1;
        BlockId id;
        if (ylo > std::max(hmax, p.sea_level)) {
            id = kAir;
        } else if (yhi < int64_t(hmin) - p.soil_depth) {
            id = m_ids.stone; // Below every column's soil (caves not carved).
        } else if (ylo > hmax) {
            id = m_ids.water; // Above every column, at or below the sea.
        } else {
            // Each block column votes for its topmost non-air block in the cell: terrain at yhi
            // when the surface is higher, the water surface when the sea covers the column
            // inside the cell, else the surface block when it is inside the cell. The vote of
            // downsample() (cell_vote.h); water is the only see-through id the terrain votes for.
            CellVote ballot;
            const auto vote = [&](BlockId v) { ballot.add(v, v != m_ids.water); };
            for (size_t j = 0; j < size_t(s) * size_t(s); ++j) {
                const int h = g.col_h[j];
                if (h >= yhi)
                    vote(yhi == h ? g.col_ids[j].top
                                  : yhi >= int64_t(h) - p.soil_depth ? g.col_ids[j].under : m_ids.stone);
                else if (p.sea_level > h && p.sea_level >= ylo)
                    vote(m_ids.water);
                else if (h >= ylo)
                    vote(g.col_ids[j].top);
            }
            id = ballot.winner();
        }
        dense[local_index(cx, y, cz)] = id;
    }
}

bool TerrainGenerator::generate_coarse(LodCoord c, Chunk& out) const {
    if (c.level < 1 || c.level > kMaxDirectLevel)
        return false;
    const TerrainParams& p = m_params;
    CoarseGrid g;
    g.origin = lod_origin(c);
    g.cell = int(lod_cell_size(c.level));
    const int64_t y0 = g.origin.y, y1 = y0 + lod_chunk_blocks(c.level) - 1;
    // The early outs of generate(), with caves never carved.
    if (y0 > std::max(height_hi(p), int64_t(p.sea_level))) {
        out = Chunk(kAir);
        return true;
    }
    if (y1 < height_lo(p) - p.soil_depth) {
        out = Chunk(m_ids.stone);
        return true;
    }
    g.n = int(lod_chunk_blocks(c.level) / kGrid) + 1;
    g.h.resize(size_t(g.n) * size_t(g.n));
    float lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < g.n; ++k)
        for (int i = 0; i < g.n; ++i) {
            const float h = coarse_height(g.origin.x + kGrid * i, g.origin.z + kGrid * k);
            g.h[size_t(k) * size_t(g.n) + size_t(i)] = h;
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
    // One block of margin: a bilinear height may round a hair above its samples, and only an
    // air cell could break the guarantee (a solid one over air is merely over-coverage).
    if (y0 > std::max(int64_t(std::floor(hi)) + 1, int64_t(p.sea_level))) {
        out = Chunk(kAir);
        return true;
    }
    if (y1 < int64_t(std::floor(lo)) - 1 - p.soil_depth) {
        out = Chunk(m_ids.stone);
        return true;
    }
    g.col_h.resize(size_t(g.cell) * size_t(g.cell));
    g.col_ids.resize(g.col_h.size());
    std::unique_ptr<BlockId[]> ids(new BlockId[kChunkVolume]);
    for (int cz = 0; cz < kChunkSize; ++cz)
        for (int cx = 0; cx < kChunkSize; ++cx)
            coarse_column(g, cx, cz, ids.get());
    out = Chunk::from_dense(std::span<const BlockId>(ids.get(), kChunkVolume));
    return true;
}

Chunk generate_terrain_chunk(uint64_t seed, ChunkCoord c) { return TerrainGenerator(seed).generate(c); }

} // namespace vx::world
