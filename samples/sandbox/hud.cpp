#include "hud.h"

#include <algorithm>
#include <cmath>

#include <imgui.h>

namespace sandbox {
namespace {

constexpr uint32_t kAtlasWidth = 640;  // Text panel width limit (pixels at scale 1).
constexpr int kLineHeight = 14;
constexpr int kPad = 3;
constexpr int kTextTop = 2;            // Atlas rows 0..1: white texel, hotbar colours.
constexpr glm::u8vec4 kPanel{16, 16, 20, 255};
constexpr glm::u8vec4 kWhite{255, 255, 255, 255};

uint8_t srgb_encode(float linear) {
    const float c = std::clamp(linear, 0.f, 1.f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
    return uint8_t(std::lround(s * 255.f));
}

void put(vx::Image& img, uint32_t x, uint32_t y, glm::u8vec4 c) {
    uint8_t* p = &img.rgba[(size_t(y) * img.width + x) * 4];
    p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = c.a;
}

} // namespace

Hud::Hud(std::vector<vx::BlockType> blocks) : m_blocks(std::move(blocks)), m_font(std::make_unique<ImFontAtlas>()) {
    m_font->AddFontDefault();
    unsigned char* pixels = nullptr;
    m_font->GetTexDataAsAlpha8(&pixels, &m_glyphs_w, &m_glyphs_h);
    m_glyphs = pixels;
}

Hud::~Hud() = default;

glm::u8vec4 Hud::block_colour(vx::BlockId id) const {
    if (id == vx::kAir || id > m_blocks.size())
        return {128, 128, 128, 255};
    const vx::BlockType& b = m_blocks[id - 1u];
    const glm::vec3 c = glm::max(b.albedo, glm::min(b.emission, glm::vec3(1.f)));
    return {srgb_encode(c.r), srgb_encode(c.g), srgb_encode(c.b), 255};
}

// Sets `lines` onto a dark panel at atlas row kTextTop, blending glyph coverage on the CPU.
void Hud::draw_text(const std::vector<std::string>& lines) {
    vx::Image& img = m_overlay.atlas;
    const ImFont* font = m_font->Fonts[0];
    int widest = 0;
    for (const std::string& l : lines)
        widest = std::max(widest, int(font->CalcTextSizeA(font->FontSize, 1e9f, 0.f, l.c_str()).x));
    m_text_w = std::min(int(kAtlasWidth), widest + 2 * kPad);
    m_text_h = int(lines.size()) * kLineHeight + 2 * kPad;
    img.width = kAtlasWidth;
    img.height = uint32_t(kTextTop + m_text_h);
    img.rgba.assign(size_t(img.width) * img.height * 4, 0);
    for (int y = 0; y < m_text_h; ++y)
        for (int x = 0; x < m_text_w; ++x)
            put(img, uint32_t(x), uint32_t(kTextTop + y), kPanel);
    for (size_t li = 0; li < lines.size(); ++li) {
        float pen = float(kPad);
        const int top = kTextTop + kPad + int(li) * kLineHeight;
        for (unsigned char ch : lines[li]) {
            const ImFontGlyph* g = font->FindGlyph(ImWchar(ch));
            if (!g)
                continue;
            const int gx = int(std::lround(g->U0 * float(m_glyphs_w))), gy = int(std::lround(g->V0 * float(m_glyphs_h)));
            const int gw = int(std::lround((g->U1 - g->U0) * float(m_glyphs_w)));
            const int gh = int(std::lround((g->V1 - g->V0) * float(m_glyphs_h)));
            for (int y = 0; y < gh; ++y)
                for (int x = 0; x < gw; ++x) {
                    const int px = int(pen + g->X0) + x, py = top + int(g->Y0) + y;
                    if (px < 0 || px >= m_text_w || py < kTextTop || py >= kTextTop + m_text_h)
                        continue;
                    const float a = float(m_glyphs[(gy + y) * m_glyphs_w + gx + x]) / 255.f;
                    const glm::vec4 c = glm::mix(glm::vec4(kPanel), glm::vec4(230, 230, 230, 255), a);
                    put(img, uint32_t(px), uint32_t(py), glm::u8vec4(c));
                }
            pen += g->AdvanceX;
        }
    }
    m_text = lines;
    m_palette.clear(); // Row 1 was cleared with the atlas.
}

const vx::Overlay& Hud::build(uint32_t width, uint32_t height, const Hotbar& hotbar, const std::vector<std::string>& lines) {
    vx::Overlay& o = m_overlay;
    const bool text_changed = lines != m_text || o.atlas.width == 0;
    if (text_changed)
        draw_text(lines);
    std::vector<vx::BlockId> palette;
    for (int i = 0; i < Hotbar::kSlots; ++i)
        palette.push_back(hotbar.slot(i));
    if (text_changed || palette != m_palette) {
        put(o.atlas, 0, 0, kWhite);
        put(o.atlas, 1, 0, {40, 40, 40, 255}); // Slot frame.
        for (int i = 0; i < Hotbar::kSlots; ++i)
            put(o.atlas, uint32_t(2 + i), 0, block_colour(palette[size_t(i)]));
        m_palette = palette;
        ++o.atlas_version;
    }
    o.rects.clear();
    const int W = int(width), H = int(height);
    const int scale = std::max(1, std::min(W, H) / 400); // Bigger HUD on big windows.
    // Crosshair: four arms, the centre pixel left free.
    const int cx = W / 2, cy = H / 2, arm = 4 * scale, t = scale;
    o.rects.push_back({0, 0, 1, 1, cx - arm - 1, cy, arm, t});
    o.rects.push_back({0, 0, 1, 1, cx + 2, cy, arm, t});
    o.rects.push_back({0, 0, 1, 1, cx, cy - arm - 1, t, arm});
    o.rects.push_back({0, 0, 1, 1, cx, cy + 2, t, arm});
    // Hotbar: bottom centre, the selected slot framed in white.
    const int slot = std::max(6, std::min(20 * scale, (W - 20) / Hotbar::kSlots)), gap = std::max(1, slot / 8);
    const int bar_w = Hotbar::kSlots * slot, x0 = (W - bar_w) / 2, y0 = H - slot - 2 * gap;
    o.rects.push_back({1, 0, 1, 1, x0 - gap, y0 - gap, bar_w + 2 * gap, slot + 2 * gap});
    for (int i = 0; i < Hotbar::kSlots; ++i) {
        const int x = x0 + i * slot;
        if (i == hotbar.selected_slot())
            o.rects.push_back({0, 0, 1, 1, x, y0 - gap, slot, slot + 2 * gap});
        o.rects.push_back({2 + i, 0, 1, 1, x + gap, y0 + gap, slot - 2 * gap, slot - 2 * gap});
    }
    // Text panel top left (cropped to the window).
    if (!lines.empty()) {
        const int w = std::min(m_text_w, (W - 4) / scale), h = std::min(m_text_h, (H / 2 - 6) / scale); // Clear of the crosshair.
        if (w > 0 && h > 0)
            o.rects.push_back({0, kTextTop, w, h, 2, 2, w * scale, h * scale});
    }
    return o;
}

} // namespace sandbox
