// Shading models and capture outputs of lighting.glsl, shared by C++ (src/gpu/frame.cpp, from
// standin::ShadingModel) and GLSL (FrameBlock.shadow_bias.y). Plain #defines: both parse this file.
#ifndef STANDIN_SHADING_MODEL_H
#define STANDIN_SHADING_MODEL_H

#define SHADING_GGX 0                 // glTF metallic-roughness: GGX/Smith + Lambert (the default)
#define SHADING_LAMBERT_BLINN_PHONG 1 // standin before issue #14; pure ambient returns the albedo
#define SHADING_CAPTURE_ORM 2         // writes occlusion, roughness, metallic (linear) instead of a colour
#define SHADING_CAPTURE_EMISSION 3    // writes the emission, sRGB-encoded and clamped to [0,1]
#define SHADING_CAPTURE_NORMAL 4      // writes the shading normal (normal map applied), turned to the eye, n * 0.5 + 0.5

#endif
