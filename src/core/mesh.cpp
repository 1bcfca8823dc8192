// The Mesh's own geometry queries (bounds, areas, albedo lookup), the invariant check every stage
// runs before trusting a mesh, smooth normals, and the binary PLY writer used for coarse meshes.
// Import lives in src/io/import_mesh.cpp; this file needs no third-party library.
#include <standin/files.h>
#include <standin/mesh.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace standin {

// ---------------------------------------------------------------------------------------------
// Texture

static int wrap_index(int i, int n)
{
    if (i >= 0 && i < n) return i; // the usual case, without a division
    int r = i % n;
    return r < 0 ? r + n : r;
}

static glm::vec4 texel(const Texture& texture, int x, int y)
{
    const std::uint8_t* p = &texture.rgba[(std::size_t(y) * texture.width + x) * 4];
    return glm::vec4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
}

namespace {

// The four texels a bilinear lookup at uv reads, and its weights (texel centres at (i + 0.5) / size).
struct BilinearFootprint {
    int x0, x1, y0, y1;
    float fx, fy;
};

// floor(x) for |x| < 2^31, exact, without the libm call x86-64's baseline (no SSE4.1) makes of it
float floor_small(float x)
{
    float t = float(int(x));
    return t > x ? t - 1.0f : t;
}

BilinearFootprint footprint(const Texture& texture, glm::vec2 uv)
{
    // reduce to one period first so float keeps its precision (uv - floor(uv) is uv itself in [0, 1))
    glm::vec2 wrapped = uv;
    if (!(uv.x >= 0.0f && uv.x < 1.0f)) wrapped.x = uv.x - std::floor(uv.x);
    if (!(uv.y >= 0.0f && uv.y < 1.0f)) wrapped.y = uv.y - std::floor(uv.y);
    float x = wrapped.x * float(texture.width) - 0.5f;
    float y = wrapped.y * float(texture.height) - 0.5f;
    float x0f = floor_small(x), y0f = floor_small(y); // x, y in [-0.5, size): sizes are below 2^31
    return {wrap_index(int(x0f), texture.width), wrap_index(int(x0f) + 1, texture.width),
            wrap_index(int(y0f), texture.height), wrap_index(int(y0f) + 1, texture.height), x - x0f, y - y0f};
}

bool sampleable(const Texture& texture)
{
    return texture.width > 0 && texture.height > 0 && texture.rgba.size() >= std::size_t(texture.width) * texture.height * 4;
}

} // namespace

glm::vec4 Texture::sample(glm::vec2 uv) const
{
    if (!sampleable(*this)) return glm::vec4(1.0f);
    // a NaN UV would turn into an arbitrary index below; the first texel is as good as any
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return texel(*this, 0, 0);
    const BilinearFootprint f = footprint(*this, uv);
    glm::vec4 bottom = glm::mix(texel(*this, f.x0, f.y0), texel(*this, f.x1, f.y0), f.fx);
    glm::vec4 top = glm::mix(texel(*this, f.x0, f.y1), texel(*this, f.x1, f.y1), f.fx);
    return glm::mix(bottom, top, f.fy);
}

float Texture::sample_alpha(glm::vec2 uv) const
{
    if (!sampleable(*this)) return 1.0f;
    auto alpha = [&](int x, int y) { return float(rgba[(std::size_t(y) * width + x) * 4 + 3]) * (1.0f / 255.0f); };
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return alpha(0, 0);
    const BilinearFootprint f = footprint(*this, uv);
    // the operations of sample() on its w: the same float
    float bottom = glm::mix(alpha(f.x0, f.y0), alpha(f.x1, f.y0), f.fx);
    float top = glm::mix(alpha(f.x0, f.y1), alpha(f.x1, f.y1), f.fx);
    return glm::mix(bottom, top, f.fy);
}

// ---------------------------------------------------------------------------------------------
// Geometry queries

Bounds Mesh::bounds() const
{
    Bounds b;
    if (positions.empty()) return b;
    b.min = b.max = positions[0];
    for (const glm::vec3& p : positions) {
        b.min = glm::min(b.min, p);
        b.max = glm::max(b.max, p);
    }
    return b;
}

BoundingSphere Mesh::bounding_sphere() const
{
    return bounding_sphere_of(bounds());
}

double Mesh::triangle_area(std::size_t triangle) const
{
    assert(triangle < triangle_count());
    // double: millions of small triangles are summed, and slivers need the precision
    glm::dvec3 a = positions[indices[triangle * 3 + 0]];
    glm::dvec3 b = positions[indices[triangle * 3 + 1]];
    glm::dvec3 c = positions[indices[triangle * 3 + 2]];
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

double Mesh::surface_area() const
{
    double sum = 0.0;
    for (std::size_t t = 0; t < triangle_count(); ++t) sum += triangle_area(t);
    return sum;
}

glm::vec4 Mesh::albedo_at(std::size_t triangle, float b1, float b2) const
{
    assert(triangle < triangle_count());
    std::uint32_t i0 = indices[triangle * 3 + 0], i1 = indices[triangle * 3 + 1], i2 = indices[triangle * 3 + 2];
    float b0 = 1.0f - b1 - b2;
    glm::vec4 color = b0 * colors[i0] + b1 * colors[i1] + b2 * colors[i2];

    // colors already include the material's base colour (see Material); only the texture is left
    const Material& material = materials[face_materials[triangle]];
    if (material.base_color_texture >= 0 && has_texture_coordinates()) {
        glm::vec2 uv = b0 * uvs[i0] + b1 * uvs[i1] + b2 * uvs[i2];
        color *= textures[std::size_t(material.base_color_texture)].sample(uv);
    }
    return color;
}

bool Mesh::covered_at(std::size_t triangle, float b1, float b2) const
{
    const Material& material = materials[face_materials[triangle]];
    float cutoff = alpha_test_cutoff(material);
    if (cutoff <= 0.0f) return true;
    // albedo_at(...).w without the colour channels: the bakes test every texel of a leaf card
    std::uint32_t i0 = indices[triangle * 3 + 0], i1 = indices[triangle * 3 + 1], i2 = indices[triangle * 3 + 2];
    float b0 = 1.0f - b1 - b2;
    float alpha = b0 * colors[i0].w + b1 * colors[i1].w + b2 * colors[i2].w;
    if (material.base_color_texture >= 0 && has_texture_coordinates()) {
        glm::vec2 uv = b0 * uvs[i0] + b1 * uvs[i1] + b2 * uvs[i2];
        alpha *= textures[std::size_t(material.base_color_texture)].sample_alpha(uv);
    }
    return alpha >= cutoff;
}

bool Mesh::has_alpha_test() const
{
    return std::any_of(materials.begin(), materials.end(),
                       [](const Material& m) { return alpha_test_cutoff(m) > 0.0f || !m.double_sided; });
}

PbrSample Mesh::pbr_at(std::size_t triangle, float b1, float b2) const
{
    assert(triangle < triangle_count());
    const Material& material = materials[face_materials[triangle]];
    PbrSample sample;
    sample.roughness = material.roughness;
    sample.metallic = material.metallic;
    sample.emissive = material.emissive;
    if (!has_texture_coordinates()) return sample;
    std::uint32_t i0 = indices[triangle * 3 + 0], i1 = indices[triangle * 3 + 1], i2 = indices[triangle * 3 + 2];
    glm::vec2 uv = (1.0f - b1 - b2) * uvs[i0] + b1 * uvs[i1] + b2 * uvs[i2];
    auto map = [&](int texture) { return textures[std::size_t(texture)].sample(uv); };
    if (material.metallic_roughness_texture >= 0) {
        glm::vec4 mr = map(material.metallic_roughness_texture);
        sample.roughness *= mr.y;
        sample.metallic *= mr.z;
    }
    if (material.occlusion_texture >= 0)
        sample.occlusion = 1.0f + material.occlusion_strength * (map(material.occlusion_texture).x - 1.0f);
    if (material.emissive_texture >= 0) {
        // the texture holds sRGB-encoded values; the factor is linear
        glm::vec3 c = glm::vec3(map(material.emissive_texture));
        glm::vec3 linear = glm::mix(c / 12.92f, glm::pow((c + 0.055f) / 1.055f, glm::vec3(2.4f)),
                                    glm::vec3(glm::greaterThan(c, glm::vec3(0.04045f))));
        sample.emissive *= linear;
    }
    return sample;
}

glm::vec3 Mesh::shading_normal_at(std::size_t triangle, float b1, float b2) const
{
    assert(triangle < triangle_count());
    std::uint32_t i0 = indices[triangle * 3 + 0], i1 = indices[triangle * 3 + 1], i2 = indices[triangle * 3 + 2];
    float b0 = 1.0f - b1 - b2;
    glm::vec3 n = b0 * normals[i0] + b1 * normals[i1] + b2 * normals[i2];
    n = glm::dot(n, n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 0.0f, 1.0f);
    const Material& material = materials[face_materials[triangle]];
    if (material.normal_texture < 0 || !has_texture_coordinates()) return n;
    // the triangle's tangent frame from its UV gradients (what a per-pixel cotangent frame gives the
    // truth renderer; Schüler 2006), made orthogonal to the interpolated normal
    glm::vec3 e1 = positions[i1] - positions[i0], e2 = positions[i2] - positions[i0];
    glm::vec2 d1 = uvs[i1] - uvs[i0], d2 = uvs[i2] - uvs[i0];
    float det = d1.x * d2.y - d2.x * d1.y;
    if (std::abs(det) < 1e-20f) return n;
    glm::vec3 t = (e1 * d2.y - e2 * d1.y) / det, b = (e2 * d1.x - e1 * d2.x) / det;
    t -= n * glm::dot(n, t);
    b -= n * glm::dot(n, b);
    if (glm::dot(t, t) < 1e-30f || glm::dot(b, b) < 1e-30f) return n;
    glm::vec2 uv = b0 * uvs[i0] + b1 * uvs[i1] + b2 * uvs[i2];
    glm::vec3 m = glm::vec3(textures[std::size_t(material.normal_texture)].sample(uv)) * 2.0f - 1.0f;
    m.x *= material.normal_scale;
    m.y *= material.normal_scale;
    // a normal map's +y points up its image; Mesh::uvs have v growing up the image (row 0 at v = 0),
    // so +y is along dP/dv
    glm::vec3 bent = m.x * glm::normalize(t) + m.y * glm::normalize(b) + m.z * n;
    return glm::dot(bent, bent) > 0.0f ? glm::normalize(bent) : n;
}

bool Mesh::has_pbr_materials() const
{
    for (const Material& material : materials)
        if (material.has_pbr()) return true;
    return false;
}

std::vector<glm::vec4> vertex_albedo(const Mesh& mesh)
{
    std::vector<glm::vec4> albedo = mesh.colors;
    if (mesh.textures.empty() || !mesh.has_texture_coordinates()) return albedo;
    std::vector<bool> done(mesh.vertex_count(), false);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Material& material = mesh.materials[mesh.face_materials[t]];
        for (int k = 0; k < 3; ++k) {
            std::uint32_t v = mesh.indices[t * 3 + k];
            if (done[v]) continue;
            done[v] = true;
            if (material.base_color_texture >= 0)
                albedo[v] *= mesh.textures[std::size_t(material.base_color_texture)].sample(mesh.uvs[v]);
        }
    }
    return albedo;
}

// ---------------------------------------------------------------------------------------------
// Invariants

static bool is_finite(glm::vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }
static bool is_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
static bool is_finite(glm::vec4 v) { return is_finite(glm::vec3(v)) && std::isfinite(v.w); }

static Status invalid(const std::string& what, const std::string& problem)
{
    return error(StatusCode::bad_data, what + ": " + problem);
}

// Index of the first element that is not finite, or size() when all are.
template <typename Vec>
static std::size_t first_non_finite(const std::vector<Vec>& values)
{
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!is_finite(values[i])) return i;
    return values.size();
}

static Status check_vertex_arrays(const Mesh& mesh, const std::string& what)
{
    std::size_t n = mesh.positions.size();
    if (mesh.normals.size() != n)
        return invalid(what, "normals has " + std::to_string(mesh.normals.size()) + " entries for " + std::to_string(n) + " vertices");
    if (mesh.colors.size() != n)
        return invalid(what, "colors has " + std::to_string(mesh.colors.size()) + " entries for " + std::to_string(n) + " vertices");
    if (!mesh.uvs.empty() && mesh.uvs.size() != n)
        return invalid(what, "uvs has " + std::to_string(mesh.uvs.size()) + " entries for " + std::to_string(n) + " vertices");
    if (std::size_t i = first_non_finite(mesh.positions); i != n)
        return invalid(what, "positions[" + std::to_string(i) + "] is not finite");
    if (std::size_t i = first_non_finite(mesh.normals); i != n)
        return invalid(what, "normals[" + std::to_string(i) + "] is not finite");
    if (std::size_t i = first_non_finite(mesh.colors); i != n)
        return invalid(what, "colors[" + std::to_string(i) + "] is not finite");
    if (std::size_t i = first_non_finite(mesh.uvs); i != mesh.uvs.size())
        return invalid(what, "uvs[" + std::to_string(i) + "] is not finite");
    return Status::ok();
}

static Status check_triangles(const Mesh& mesh, const std::string& what)
{
    if (mesh.indices.empty()) return invalid(what, "has no triangles");
    if (mesh.indices.size() % 3 != 0)
        return invalid(what, "indices has " + std::to_string(mesh.indices.size()) + " entries, not a multiple of 3");
    for (std::size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.positions.size())
            return invalid(what, "indices[" + std::to_string(i) + "] = " + std::to_string(mesh.indices[i]) +
                                     " is out of range for " + std::to_string(mesh.positions.size()) + " vertices");
    if (mesh.face_materials.size() != mesh.triangle_count())
        return invalid(what, "face_materials has " + std::to_string(mesh.face_materials.size()) + " entries for " +
                                 std::to_string(mesh.triangle_count()) + " triangles");
    for (std::size_t t = 0; t < mesh.face_materials.size(); ++t)
        if (mesh.face_materials[t] >= mesh.materials.size())
            return invalid(what, "face_materials[" + std::to_string(t) + "] = " + std::to_string(mesh.face_materials[t]) +
                                     " is out of range for " + std::to_string(mesh.materials.size()) + " materials");
    return Status::ok();
}

static Status check_materials(const Mesh& mesh, const std::string& what)
{
    if (mesh.materials.empty()) return invalid(what, "has no material");
    for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
        const Material& material = mesh.materials[m];
        std::string field = "materials[" + std::to_string(m) + "]";
        if (!is_finite(material.base_color)) return invalid(what, field + ".base_color is not finite");
        int t = material.base_color_texture;
        if (t < -1 || t >= int(mesh.textures.size()))
            return invalid(what, field + ".base_color_texture = " + std::to_string(t) + " is out of range");
        if (t >= 0 && mesh.uvs.empty()) return invalid(what, field + " has a texture but the mesh has no uvs");
        if (!std::isfinite(material.alpha_cutoff) || material.alpha_cutoff < 0.0f || material.alpha_cutoff > 1.0f)
            return invalid(what, field + ".alpha_cutoff = " + std::to_string(material.alpha_cutoff) + " is outside [0, 1]");
        std::pair<const char*, int> maps[] = {{"metallic_roughness_texture", material.metallic_roughness_texture},
                                              {"occlusion_texture", material.occlusion_texture},
                                              {"emissive_texture", material.emissive_texture},
                                              {"normal_texture", material.normal_texture}};
        for (auto [name, index] : maps)
            if (index < -1 || index >= int(mesh.textures.size()))
                return invalid(what, field + "." + name + " = " + std::to_string(index) + " is out of range");
        if (!std::isfinite(material.metallic) || !std::isfinite(material.roughness) || !is_finite(material.emissive) ||
            !std::isfinite(material.occlusion_strength) || !std::isfinite(material.normal_scale))
            return invalid(what, field + " has a non-finite PBR factor");
    }
    for (std::size_t t = 0; t < mesh.textures.size(); ++t) {
        const Texture& texture = mesh.textures[t];
        if (texture.width <= 0 || texture.height <= 0 ||
            texture.rgba.size() != std::size_t(texture.width) * std::size_t(texture.height) * 4)
            return invalid(what, "textures[" + std::to_string(t) + "] ('" + texture.name + "') has " +
                                     std::to_string(texture.rgba.size()) + " bytes for " + std::to_string(texture.width) +
                                     "x" + std::to_string(texture.height) + " RGBA");
    }
    return Status::ok();
}

Status validate_mesh(const Mesh& mesh, const std::string& what)
{
    STANDIN_RETURN_IF_ERROR(check_vertex_arrays(mesh, what));
    STANDIN_RETURN_IF_ERROR(check_materials(mesh, what)); // before face_materials is checked against them
    STANDIN_RETURN_IF_ERROR(check_triangles(mesh, what));
    return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// Normals

void compute_smooth_normals(Mesh& mesh)
{
    // the unnormalised cross product is twice the triangle's area times its normal: summing it
    // weights every face by its area without a square root per face
    std::vector<glm::vec3> sums(mesh.positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        std::uint32_t i0 = mesh.indices[t * 3 + 0], i1 = mesh.indices[t * 3 + 1], i2 = mesh.indices[t * 3 + 2];
        glm::vec3 p0 = mesh.positions[i0];
        glm::vec3 weighted = glm::cross(mesh.positions[i1] - p0, mesh.positions[i2] - p0);
        sums[i0] += weighted;
        sums[i1] += weighted;
        sums[i2] += weighted;
    }
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < sums.size(); ++v) {
        float length = glm::length(sums[v]);
        mesh.normals[v] = length > 0.0f && std::isfinite(length) ? sums[v] / length : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

// ---------------------------------------------------------------------------------------------
// PLY writer

static_assert(std::endian::native == std::endian::little, "write_ply copies floats as little-endian bytes");

static std::uint8_t to_unorm8(float value)
{
    if (!(value > 0.0f)) return 0; // also NaN
    if (value >= 1.0f) return 255;
    return std::uint8_t(std::lround(value * 255.0f));
}

static std::string ply_header(const Mesh& mesh)
{
    // fixed text: the same mesh must give the same bytes (packages are hashed)
    return "ply\n"
           "format binary_little_endian 1.0\n"
           "comment generator standin\n"
           "element vertex " + std::to_string(mesh.vertex_count()) + "\n"
           "property float x\nproperty float y\nproperty float z\n"
           "property float nx\nproperty float ny\nproperty float nz\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
           "element face " + std::to_string(mesh.triangle_count()) + "\n"
           "property list uchar uint vertex_indices\n"
           "end_header\n";
}

static void write_ply_body(const Mesh& mesh, std::ostream& out)
{
    std::vector<glm::vec4> albedo = vertex_albedo(mesh);
    // one vertex is 6 floats and 4 bytes; buffer a few thousand at a time
    std::string buffer;
    buffer.reserve(1 << 16);
    auto flush_if_full = [&] {
        if (buffer.size() > (1 << 16) - 64) {
            out.write(buffer.data(), std::streamsize(buffer.size()));
            buffer.clear();
        }
    };
    auto put = [&](const void* data, std::size_t size) { buffer.append(static_cast<const char*>(data), size); };

    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        glm::vec3 n = v < mesh.normals.size() ? mesh.normals[v] : glm::vec3(0.0f, 0.0f, 1.0f);
        float floats[6] = {mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z, n.x, n.y, n.z};
        std::uint8_t rgba[4] = {to_unorm8(albedo[v].x), to_unorm8(albedo[v].y), to_unorm8(albedo[v].z), to_unorm8(albedo[v].w)};
        put(floats, sizeof floats);
        put(rgba, sizeof rgba);
        flush_if_full();
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        std::uint8_t count = 3;
        put(&count, 1);
        put(&mesh.indices[t * 3], 3 * sizeof(std::uint32_t));
        flush_if_full();
    }
    out.write(buffer.data(), std::streamsize(buffer.size()));
}

Status write_ply(const Mesh& mesh, const std::string& path)
{
    STANDIN_RETURN_IF_ERROR(validate_mesh(mesh, path));
    STANDIN_RETURN_IF_ERROR(check_output_path(path));
    std::string temporary = temporary_path_for(path);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return error(StatusCode::io_error, path + ": cannot create '" + temporary + "'");
        std::string header = ply_header(mesh);
        out.write(header.data(), std::streamsize(header.size()));
        write_ply_body(mesh, out);
        out.flush();
        if (!out) {
            out.close();
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
            return error(StatusCode::io_error, path + ": writing failed (disk full?)");
        }
    }
    return commit_path(temporary, path);
}

} // namespace standin
