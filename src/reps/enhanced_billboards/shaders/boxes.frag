#version 450 core
// Debug view "boxes": box lines drawn twice over the stand-in without writing depth, dimmed where
// the stand-in hides them (line_alpha < 1, blended) and at full colour where they are in front.
in vec3 v_color;

uniform float line_alpha;

layout(location = 0) out vec4 out_color;

void main() { out_color = vec4(v_color, line_alpha); }
