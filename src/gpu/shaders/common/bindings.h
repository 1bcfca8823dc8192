// Binding points and attribute locations, included by C++ (src/gpu/frame.h) and by GLSL, so the
// two sides cannot disagree. Plain #defines only: both languages must parse this file.
// The GPU layer reserves the slots below for what every renderer shares (the frame, its instances,
// the counters, the shadow map); a renderer owns every slot from BINDING_FIRST_RENDERER_* on and
// allocates them in its own layout header, relative to these (renderers never draw interleaved,
// so two renderers may use the same numbers).
#ifndef STANDIN_BINDINGS_H
#define STANDIN_BINDINGS_H

// uniform blocks
#define BINDING_FRAME_UBO 0
// shader storage blocks
#define BINDING_INSTANCES_SSBO 0
#define BINDING_COUNTERS_SSBO 1       // gpu/counters.h, shaders/common/counters.glsl
#define BINDING_FIRST_RENDERER_SSBO 2
// texture units (GL 4.5 guarantees 16 per fragment stage; renderers that use more check
// GL_MAX_TEXTURE_IMAGE_UNITS)
#define BINDING_SHADOW_TEXTURE 0      // the shadow map (render.h ShadowMap), when a frame has one
#define BINDING_FIRST_RENDERER_TEXTURE 1
// image units: all the renderer's
#define BINDING_FIRST_RENDERER_IMAGE 0
// vertex attributes
#define ATTRIB_POSITION 0
#define ATTRIB_NORMAL 1
#define ATTRIB_COLOR 2
#define ATTRIB_UV 3
#define ATTRIB_FIRST_RENDERER 4

#endif
