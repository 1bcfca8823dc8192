// The ground-truth renderer: the original mesh, drawn per pixel with the shared lighting include.
// Steps: sort triangles by material so each material is one instanced draw; upload positions,
// normals, colours and UVs; per frame bind the frame block and draw each material range with its
// texture (or none), its PBR factors and maps (issue #14), its alpha test and its face culling.
// Alpha (issue #14): mask (and blend, drawn as mask) materials discard fragments whose alpha is
// under the cutoff. The test reads the texture's full-resolution level at the fragment's UV (a
// point sample of the cut-out), whatever mip level the colour comes from: averaged alpha in the
// coarse mips of a cut-out is no coverage (a disc's mip 1 x 1 holds pi/4 everywhere, which passes
// 0.5: distant leaves would fatten into cards), while a point sample per pixel covers each pixel
// with the probability of its area being covered, so distant foliage keeps its area on average.
// Single-sided materials (glTF doubleSided false) cull back faces; the rest draw both sides.
// Mip levels of a texture with any alpha under 255 are coverage-weighted (each level's colour is
// the mean of the finer texels' colours weighted by their alpha; alpha their plain mean), not
// glGenerateMipmap's plain means: the colour of a cut-out's empty texels is arbitrary (black in most
// files), and plain means pull it into the leaf as soon as the texture is minified, so the truth's
// leaves darkened with distance and with the screen's resolution. Textures without alpha keep
// glGenerateMipmap's levels (the same as before issue #14).
#include "gpu/frame.h"
#include "gpu/gl.h"
#include "gpu/mesh_buffers.h"
#include "gpu/source_texture.h"
#include "gpu/shaders/common/bindings.h"

#include <standin/render.h>

#include <algorithm>
#include <cmath>
#include <numeric>

// this target's shaders, registered at static initialisation (cmake/shaders.cmake)
#include "embedded_shaders.inc"

namespace standin {

namespace {

struct MaterialRange {
    std::uint32_t first_index = 0, index_count = 0;
    int texture = -1;            // index into MeshRenderer::textures_
    float alpha_cutoff = 0.0f;   // alpha_test_cutoff(material): 0 tests nothing
    bool double_sided = true;
    // the material's PBR inputs (mesh.frag); maps are MeshRenderer::textures_ indices, -1 for none
    glm::vec4 pbr_factors{0.0f, 1.0f, 1.0f, 1.0f}; // metallic, roughness, occlusion strength, normal scale
    glm::vec3 emissive{0.0f};
    int maps[4] = {-1, -1, -1, -1};                 // metallic-roughness, occlusion, emissive, normal
};

class MeshRenderer final : public Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(const Mesh& mesh);
    DrawStats draw(const DrawParams& params) override;

private:
    void bind_pbr(const MaterialRange& range);

    gpu::Program program_;
    gpu::MeshBuffers buffers_;
    std::vector<gpu::Texture> textures_;
    std::vector<MaterialRange> ranges_;
    gpu::FrameResources frame_;
    GLint has_texture_location_ = -1;
    GLint alpha_cutoff_location_ = -1;
    GLint cull_in_shader_location_ = -1;
    GLint pbr_factors_location_ = -1, emissive_factor_location_ = -1, pbr_maps_location_ = -1;
};

void set_pbr(const Mesh& mesh, const Material& m, MaterialRange& range)
{
    range.pbr_factors = {m.metallic, m.roughness, m.occlusion_strength, m.normal_scale};
    range.emissive = m.emissive;
    if (!mesh.has_texture_coordinates()) return;
    const int maps[4] = {m.metallic_roughness_texture, m.occlusion_texture, m.emissive_texture, m.normal_texture};
    std::copy(maps, maps + 4, range.maps);
}

// Indices reordered so that each material's triangles are contiguous (stable: original order kept
// within a material, so the result does not depend on anything but the mesh).
std::vector<std::uint32_t> indices_by_material(const Mesh& mesh, std::vector<MaterialRange>& ranges)
{
    std::vector<std::uint32_t> order(mesh.triangle_count());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return mesh.face_materials[a] < mesh.face_materials[b]; });
    std::vector<std::uint32_t> indices;
    indices.reserve(mesh.indices.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        std::uint32_t t = order[i];
        std::uint32_t material = mesh.face_materials[t];
        if (ranges.empty() || i == 0 || mesh.face_materials[order[i - 1]] != material) {
            MaterialRange range;
            range.first_index = std::uint32_t(indices.size());
            const Material& m = mesh.materials[material];
            range.texture = mesh.has_texture_coordinates() ? m.base_color_texture : -1;
            range.alpha_cutoff = alpha_test_cutoff(m);
            range.double_sided = m.double_sided;
            set_pbr(mesh, m, range);
            ranges.push_back(range);
        }
        for (int k = 0; k < 3; ++k) indices.push_back(mesh.indices[3 * t + k]);
        ranges.back().index_count += 3;
    }
    return indices;
}

Result<std::unique_ptr<Renderer>> MeshRenderer::create(const Mesh& mesh)
{
    STANDIN_RETURN_IF_ERROR(validate_mesh(mesh, "mesh renderer"));
    auto renderer = std::make_unique<MeshRenderer>();
    Result<gpu::Program> program = gpu::Program::create({"reference/shaders/mesh.vert", "reference/shaders/mesh.frag"});
    if (!program) return program.status();
    renderer->program_ = std::move(*program);
    renderer->has_texture_location_ = renderer->program_.uniform("has_texture");
    renderer->alpha_cutoff_location_ = renderer->program_.uniform("alpha_cutoff");
    renderer->cull_in_shader_location_ = renderer->program_.uniform("cull_in_shader");
    renderer->pbr_factors_location_ = renderer->program_.uniform("pbr_factors");
    renderer->emissive_factor_location_ = renderer->program_.uniform("emissive_factor");
    renderer->pbr_maps_location_ = renderer->program_.uniform("pbr_maps");

    std::vector<std::uint32_t> indices = indices_by_material(mesh, renderer->ranges_);
    renderer->buffers_ = gpu::MeshBuffers::upload(mesh, indices);
    for (const Texture& texture : mesh.textures) renderer->textures_.push_back(gpu::upload_source_texture(texture));
    return std::unique_ptr<Renderer>(std::move(renderer));
}

void MeshRenderer::bind_pbr(const MaterialRange& range)
{
    glUniform4fv(pbr_factors_location_, 1, &range.pbr_factors.x);
    glUniform3fv(emissive_factor_location_, 1, &range.emissive.x);
    GLint has[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4; ++k) {
        if (range.maps[k] < 0 || range.maps[k] >= int(textures_.size())) continue;
        has[k] = 1;
        glBindTextureUnit(GLuint(BINDING_FIRST_RENDERER_TEXTURE + 1 + k), textures_[std::size_t(range.maps[k])].get());
    }
    glUniform4iv(pbr_maps_location_, 1, has);
}

DrawStats MeshRenderer::draw(const DrawParams& params)
{
    frame_.bind(params);
    program_.use();
    buffers_.bind();
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    DrawStats stats;
    // single-sided materials cull back faces; a mirroring instance transform turns its front faces'
    // winding, and one draw holds every instance: where any mirrors, mesh.frag culls instead (by
    // gl_FrontFacing and the instance's handedness)
    const bool mirrors = frame_.any_instance_mirrors();
    for (const MaterialRange& range : ranges_) {
        bool textured = range.texture >= 0 && range.texture < int(textures_.size());
        glUniform1i(has_texture_location_, textured ? 1 : 0);
        glUniform1f(alpha_cutoff_location_, range.alpha_cutoff);
        glUniform1i(cull_in_shader_location_, !range.double_sided && mirrors ? 1 : 0);
        if (range.double_sided || mirrors) {
            glDisable(GL_CULL_FACE);
        } else {
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
            glFrontFace(GL_CCW);
        }
        if (textured) glBindTextureUnit(BINDING_FIRST_RENDERER_TEXTURE, textures_[std::size_t(range.texture)].get());
        bind_pbr(range);
        glDrawElementsInstanced(GL_TRIANGLES, GLsizei(range.index_count), GL_UNSIGNED_INT,
                                reinterpret_cast<const void*>(std::uintptr_t(range.first_index) * sizeof(std::uint32_t)),
                                GLsizei(frame_.instance_count()));
        stats.draw_calls += 1;
        stats.primitives += std::uint64_t(range.index_count / 3) * frame_.instance_count();
    }
    glDisable(GL_CULL_FACE);
    glBindVertexArray(0);
    return stats;
}

} // namespace

Result<std::unique_ptr<Renderer>> make_mesh_renderer(const Mesh& mesh) { return MeshRenderer::create(mesh); }

} // namespace standin
