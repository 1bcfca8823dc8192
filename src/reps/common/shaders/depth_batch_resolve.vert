#version 450 core
// Depth batches' resolve (reps/common/depth_batches.h): one triangle over the viewport.
void main()
{
    const vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
