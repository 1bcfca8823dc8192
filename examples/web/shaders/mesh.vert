#version 300 es
// Plain meshes in the web viewer (the original model, and stand-ins exported as meshes), shaded as
// standin shades every mesh (src/gpu/shaders/common/lighting.glsl), so that the two halves of the
// viewer differ by the representation, not by the lighting. Optional attributes by #define:
// HAS_COLOR (color: linear RGBA), HAS_UV (uv, for base_color_map).
precision highp float;

in vec3 position;
in vec3 normal;
#ifdef HAS_COLOR
in vec4 color;
#endif
#ifdef HAS_UV
in vec2 uv;
#endif
uniform mat4 projectionMatrix;
uniform mat4 modelViewMatrix;
uniform mat4 modelMatrix;

out vec3 v_normal_world;
out vec3 v_position_world;
out vec4 v_color;
out vec2 v_uv;

void main()
{
    v_normal_world = mat3(modelMatrix) * normal;
    v_position_world = (modelMatrix * vec4(position, 1.0)).xyz;
#ifdef HAS_COLOR
    v_color = color;
#else
    v_color = vec4(1.0);
#endif
#ifdef HAS_UV
    v_uv = uv;
#else
    v_uv = vec2(0.0);
#endif
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}
