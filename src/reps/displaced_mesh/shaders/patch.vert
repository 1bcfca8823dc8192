#version 450 core
// Tessellation baseline: one patch of three control vertices per control face and instance.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"

flat out uint vc_face;
flat out uint vc_instance;

void main()
{
    vc_face = uint(gl_VertexID / 3);
    vc_instance = uint(gl_InstanceID);
    gl_Position = vec4(0.0);
}
