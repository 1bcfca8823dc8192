#version 300 es
// Grid-atlas impostor, vertex stage (WebGL2 / GLSL ES 3.00): the reference for drawing the
// `grid-impostor` node of a .glb written by `standin export` (docs/FORMAT.md, "Export"), used as is
// by examples/web (three.js RawShaderMaterial: three adds nothing but this file's own #defines).
// Draws a camera-facing square around the bounding sphere, large enough to hold the sphere's whole
// projection: in perspective the sphere's outline is a cone of half-angle asin(r / D) from the eye,
// which cuts the plane through the centre in a circle of radius r D / sqrt(D^2 - r^2) > r (a quad of
// the frames' own half side h = r would clip the parts of the model nearer the eye).
// With HULL defined (the `grid-impostor-hull` node, issue #16) the vertices are the atlas hull's,
// drawn as they are: a convex polytope around the model, so that far fewer pixels than the
// square's run the fragment stage, which needs only each pixel's eye ray (the same ray as through
// the square) and so is unchanged. The hull is drawn with its back faces (three.BackSide): they
// cover the same pixels as the front ones, and still do when the eye is inside the hull.
// Attributes: position (the corners of the square [-1, 1]^2, z ignored; with HULL, the hull's
// vertices in object space).
// Uniforms (object space = the source model's, the glTF's):
//   projectionMatrix, modelViewMatrix: three.js's (clip <- view <- object)
//   eye_object: the camera position (perspective) in object space
//   forward_object, orthographic: the view direction and 1 for parallel projection
//   center, radius: the bounding sphere (extras "center", "radius")
precision highp float;

in vec3 position;
uniform mat4 projectionMatrix;
uniform mat4 modelViewMatrix;
uniform vec3 eye_object;
uniform vec3 forward_object;
uniform int orthographic;
uniform vec3 center;
uniform float radius;

out vec3 v_position_object;

void main()
{
#ifdef HULL
    v_position_object = position;
    gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
#else
    vec3 to_eye = orthographic == 1 ? -forward_object : eye_object - center;
    float distance_to_center = length(to_eye);
    vec3 w = to_eye / max(distance_to_center, 1e-20);
    vec3 up = abs(w.y) > 0.999 ? vec3(0.0, 0.0, w.y > 0.0 ? -1.0 : 1.0) : vec3(0.0, 1.0, 0.0);
    vec3 right = normalize(cross(up, w));
    vec3 top = cross(w, right);
    float half_side = radius;
    if (orthographic == 0)
        half_side = distance_to_center > 1.001 * radius
                        ? radius * distance_to_center / sqrt(distance_to_center * distance_to_center - radius * radius)
                        : 1e3 * radius; // the eye inside the sphere: cover the screen
    // 1 % margin: the outline's texels are not cut by rasterisation at the quad's edge
    vec3 p = center + (position.x * right + position.y * top) * half_side * 1.01;
    v_position_object = p;
    gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
#endif
}
