#version 300 es
// Enhanced billboard, vertex stage (WebGL2 / GLSL ES 3.00): the reference for drawing a
// `role: "billboard"` node of a .glb written by `standin export` (docs/FORMAT.md, "Export"), used
// as is by examples/web. The node's mesh is the billboard's box; it is drawn by its back faces
// (culling the front ones) so that every pixel the box covers runs billboard.frag once, with the
// eye outside the box or inside it.
// Attributes: position (object space). Uniforms: three.js's projectionMatrix, modelViewMatrix.
precision highp float;

in vec3 position;
uniform mat4 projectionMatrix;
uniform mat4 modelViewMatrix;

out vec3 v_position_object;

void main()
{
    v_position_object = position;
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}
