#include "world/vdb/vdb_meta.h"

#include <cstring>
#include <optional>

namespace vx::vdb::detail {
namespace {

template <class T> std::string pod_bytes(const T& v) { return std::string(reinterpret_cast<const char*>(&v), sizeof v); }

VdbMetaValue meta_vec3s(glm::vec3 v) {
    const float f[3] = {v.x, v.y, v.z};
    return {"vec3s", std::string(reinterpret_cast<const char*>(f), sizeof f)};
}

std::string block_key(int id, const char* field) { return "vx_block_" + std::to_string(id) + "_" + field; }

// The item's value when it has the expected type and size, else nullopt (absent) or an error.
template <class T> Result<std::optional<T>> get(const VdbMetaMap& meta, const std::string& key, const char* type) {
    auto it = meta.find(key);
    if (it == meta.end())
        return std::optional<T>();
    if (it->second.type != type || it->second.bytes.size() != sizeof(T))
        return Error{"metadata " + key + " is a " + it->second.type.substr(0, 32) + " of " +
                     std::to_string(it->second.bytes.size()) + " bytes, not a " + type};
    T v;
    std::memcpy(&v, it->second.bytes.data(), sizeof v);
    return std::optional<T>(v);
}

struct Vec3 {
    float v[3];
};

} // namespace

VdbMetaValue meta_int32(int32_t v) { return {"int32", pod_bytes(v)}; }
VdbMetaValue meta_int64(int64_t v) { return {"int64", pod_bytes(v)}; }
VdbMetaValue meta_string(std::string v) { return {"string", std::move(v)}; }

void add_registry_meta(VdbMetaMap& meta, const world::BlockRegistry& registry) {
    meta["vx_block_table_size"] = meta_int32(int32_t(registry.size()));
    for (size_t i = 1; i < registry.size(); ++i) {
        const world::BlockId id = world::BlockId(i);
        if (!registry.contains(id))
            continue;
        const world::BlockInfo b = registry.info(id);
        meta[block_key(int(i), "name")] = meta_string(b.name);
        meta[block_key(int(i), "albedo")] = meta_vec3s(b.albedo);
        meta[block_key(int(i), "reflectivity")] = {"float", pod_bytes(b.reflectivity)};
        meta[block_key(int(i), "emission")] = meta_vec3s(b.emission);
        meta[block_key(int(i), "opaque")] = {"bool", std::string(1, b.opaque ? '\1' : '\0')};
    }
}

Result<world::BlockRegistry> registry_from_meta(const VdbMetaMap& meta) {
    auto table = get<int32_t>(meta, "vx_block_table_size", "int32");
    if (!table)
        return Error{table.error()};
    if (!*table)
        return world::BlockRegistry::default_registry();
    const int32_t n = **table;
    if (n < 1 || n > 0x10000)
        return Error{"metadata vx_block_table_size = " + std::to_string(n) + " is out of range 1..65536"};
    world::BlockRegistry r;
    for (int i = 1; i < n; ++i) {
        auto name = meta.find(block_key(i, "name"));
        if (name == meta.end())
            continue;
        if (name->second.type != "string")
            return Error{"metadata " + name->first + " is not a string"};
        world::BlockInfo b;
        b.name = name->second.bytes;
        auto albedo = get<Vec3>(meta, block_key(i, "albedo"), "vec3s");
        auto reflectivity = get<float>(meta, block_key(i, "reflectivity"), "float");
        auto emission = get<Vec3>(meta, block_key(i, "emission"), "vec3s");
        auto opaque = get<uint8_t>(meta, block_key(i, "opaque"), "bool"); // A byte: any value but 0 is true.
        for (const std::string* e : {albedo ? nullptr : &albedo.error(), reflectivity ? nullptr : &reflectivity.error(),
                                     emission ? nullptr : &emission.error(), opaque ? nullptr : &opaque.error()})
            if (e)
                return Error{*e};
        if (*albedo)
            b.albedo = glm::vec3((*albedo)->v[0], (*albedo)->v[1], (*albedo)->v[2]);
        if (*reflectivity)
            b.reflectivity = **reflectivity;
        if (*emission)
            b.emission = glm::vec3((*emission)->v[0], (*emission)->v[1], (*emission)->v[2]);
        if (*opaque)
            b.opaque = **opaque != 0;
        // set() refuses a NaN, infinite or out-of-range material (world::material_problem).
        if (Status s = r.set(world::BlockId(i), std::move(b)); !s)
            return Error{"block " + std::to_string(i) + " in the file's registry: " + s.error()};
    }
    return r;
}

} // namespace vx::vdb::detail
