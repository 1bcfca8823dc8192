// Binding points and attribute locations, included by C++ (src/gpu/frame.h) and by GLSL, so the
// two sides cannot disagree. Plain #defines only: both languages must parse this file.
#ifndef STANDIN_BINDINGS_H
#define STANDIN_BINDINGS_H

// uniform blocks
#define BINDING_FRAME_UBO 0
// shader storage blocks
#define BINDING_INSTANCES_SSBO 0
#define BINDING_BILLBOARDS_SSBO 1
#define BINDING_COUNTERS_SSBO 2
// texture units
#define BINDING_ALBEDO_TEXTURE 0
#define BINDING_NORMAL_DEPTH_TEXTURE 1
#define BINDING_ACCELERATION_TEXTURE 2
#define BINDING_EXTRA_TEXTURE 3
#define BINDING_SHADOW_TEXTURE 16 // above the view atlas' 0..15 (16+ units: every GL 4.5 driver we run on has 32)
// vertex attributes
#define ATTRIB_POSITION 0
#define ATTRIB_NORMAL 1
#define ATTRIB_COLOR 2
#define ATTRIB_UV 3

#endif
