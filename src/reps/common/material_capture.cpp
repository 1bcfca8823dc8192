// Material channels of a GPU capture: the ground truth drawn in its capture modes (material_capture.h).
// One pass per channel rather than a second fragment program with two outputs: mesh.frag already
// computes ORM and emission for shade_pbr, and the capture modes return them, so there is one
// definition of the material inputs (factors, maps, alpha test) for the truth and the bakers.
#include "reps/common/material_capture.h"

#include "gpu/gl.h"

namespace standin::reps {

Result<MaterialImages> capture_material(Renderer& truth, const RenderTarget& target, DrawParams params)
{
    MaterialImages out;
    const float transparent[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (ShadingModel mode : {ShadingModel::capture_orm, ShadingModel::capture_emission}) {
        params.light.shading = mode;
        target.bind();
        target.clear(transparent);
        truth.draw(params);
        (mode == ShadingModel::capture_orm ? out.orm : out.emission) = target.read_color();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "material capture: " + gpu::gl_error_text(e));
    return out;
}

} // namespace standin::reps
