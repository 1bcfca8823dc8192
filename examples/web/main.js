// standin web viewer: a stand-in exported by `standin export` (a .glb) next to the original model,
// orbited by one camera. WebGL2 through three.js; the grid-atlas impostor is drawn by
// shaders/grid_impostor.{vert,frag}, the reference GLSL for that format (docs/FORMAT.md, "Export"),
// billboards by shaders/billboard.{vert,frag}, plain meshes by shaders/mesh.{vert,frag}, all with
// standin's lighting. Colour textures may be PNG or KTX2 (KHR_texture_basisu, tools/ktx2.mjs).
//
// URL parameters (all optional; a test drives the viewer through them, README.md):
//   model=URL      the original model: .glb/.gltf, .ply or .obj
//   standin=URL    the exported stand-in (.glb)
//   view=both|model|standin   side by side (default when both are given), or one alone
//   azimuth, elevation (degrees), distance (relative), fov (degrees), ortho=1: standin's orbit
//                  camera (include/standin/camera.h): around the bounding sphere of the model's box,
//                  distance 1 = radius / sin(fov / 2), +Y up; defaults 0, 0, 1, 40, as `standin render`
//   size=WxH       the drawing size in pixels (default: the window)
//   blend=1|3      impostor frames blended (default 3); steps=N grid impostor: the most texels its
//                  walk crosses per frame (default 1024)
//   billboards=plain          billboard boxes as textured meshes instead of the ray cast
//   coarse=near-misses  billboards: the coarse mesh only where a billboard ray came near a
//                  surface and missed (standin's --coarse-fill near-misses), not on every pixel
//                  without a hit (the default, standin's; the stencil, see billboard());
//   coarse=all     the coarse mesh everywhere, depth-tested against the billboards' hits
//   proxy=quad     grid impostor: draw on the camera-facing quad even when the file has the atlas
//                  hull (role grid-impostor-hull, drawn by default)
//   still=1        no animation and no mouse orbit: render once, then set window.standin.ready
//   spin=DEG       degrees of azimuth per second while not still (default 10)
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import { PLYLoader } from 'three/addons/loaders/PLYLoader.js';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { parse_png, unfilter_png, expand_rgba16 } from './png.mjs';

const params = new URLSearchParams(location.search);
const number = (name, fallback) => {
    const v = params.get(name);
    if (v === null || v === '') return fallback;
    const n = Number(v);
    if (!Number.isFinite(n)) throw new Error(`URL parameter ${name}=${v} is not a number`);
    return n;
};

// what the page reports to a test: ready, error, and the helpers below
window.standin = { ready: false, error: null, info: {} };

// standin's default light (src/core/camera.cpp default_light): from above-left of the camera,
// ambient 0.2, diffuse 0.8
const k_light_view = new THREE.Vector3(-0.4, 0.6, 1.0).normalize();
const k_light_terms = new THREE.Vector2(0.2, 0.8);
// the albedo standin gives a model without colours or materials (src/io/import_mesh.cpp): 0.8, sRGB
const k_unauthored = new THREE.Color().setRGB(0.8, 0.8, 0.8, THREE.SRGBColorSpace);

async function fetch_text(url) {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
    return response.text();
}

// three adds `#version 300 es` itself (glslVersion GLSL3); the files carry it for glslangValidator
const strip_version = (text) => text.replace(/^#version[^\n]*\n/, '');

async function load_shaders() {
    const names = ['mesh.vert', 'mesh.frag', 'grid_impostor.vert', 'grid_impostor.frag', 'billboard.vert', 'billboard.frag'];
    const texts = await Promise.all(names.map((n) => fetch_text(new URL(`shaders/${n}`, import.meta.url))));
    return Object.fromEntries(names.map((n, i) => [n, strip_version(texts[i])]));
}

function extension_of(url) {
    const path = new URL(url, location.href).pathname.toLowerCase();
    const dot = path.lastIndexOf('.');
    return dot < 0 ? '' : path.slice(dot + 1);
}

async function load_model(url) {
    const ext = extension_of(url);
    if (ext === 'glb' || ext === 'gltf') return { object: (await gltf_loader().loadAsync(url)).scene };
    if (ext === 'ply') {
        const geometry = await new PLYLoader().loadAsync(url);
        if (!geometry.getAttribute('normal')) geometry.computeVertexNormals();
        const colored = !!geometry.getAttribute('color');
        const material = new THREE.MeshBasicMaterial({ vertexColors: colored });
        if (!colored) material.color.copy(k_unauthored);
        return { object: new THREE.Mesh(geometry, material) };
    }
    if (ext === 'obj') {
        const object = await new OBJLoader().loadAsync(url);
        object.traverse((node) => {
            if (node.isMesh && !node.geometry.getAttribute('color') && !node.material.map) node.material.color.copy(k_unauthored);
        });
        return { object };
    }
    throw new Error(`${url}: the viewer reads .glb, .gltf, .ply and .obj models`);
}

// glTF with KHR_texture_basisu (colour maps as KTX2 / Basis Universal, examples/web/tools/ktx2.mjs):
// three's KTX2Loader transcodes them, in a worker, with the Basis transcoder three ships
// (node_modules/three/examples/jsm/libs/basis/), to a block format this GPU samples (ASTC, BPTC,
// ETC2, S3TC, ..., else RGBA8); it needs the renderer to know which, so main() sets it up first
let ktx2_loader = null;
function gltf_loader() {
    const loader = new GLTFLoader();
    if (ktx2_loader) loader.setKTX2Loader(ktx2_loader);
    return loader;
}

// standin's shading for a plain mesh: its glTF/three material becomes mesh.{vert,frag}
function mesh_material(shaders, source, geometry) {
    const defines = {};
    if (geometry.getAttribute('color')) defines.HAS_COLOR = 1;
    const map = source && source.map ? source.map : null;
    if (map && geometry.getAttribute('uv')) {
        defines.HAS_UV = 1;
        defines.HAS_MAP = 1;
    }
    const base = source && source.color ? source.color : new THREE.Color(1, 1, 1);
    const opacity = source && source.opacity !== undefined ? source.opacity : 1;
    const cutoff = source && source.alphaTest > 0 ? source.alphaTest : 0;
    return new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader: shaders['mesh.vert'],
        fragmentShader: shaders['mesh.frag'],
        defines,
        side: THREE.DoubleSide,
        uniforms: {
            base_color: { value: new THREE.Vector4(base.r, base.g, base.b, opacity) },
            alpha_cutoff: { value: cutoff },
            to_light_world: { value: new THREE.Vector3(0, 0, 1) },
            light_terms: { value: k_light_terms },
            base_color_map: { value: map },
        },
    });
}

function use_mesh_materials(root, shaders) {
    root.traverse((node) => {
        if (!node.isMesh) return;
        const source = Array.isArray(node.material) ? node.material[0] : node.material;
        if (!node.geometry.getAttribute('normal')) node.geometry.computeVertexNormals();
        node.material = mesh_material(shaders, source, node.geometry);
    });
}

// the octahedral frame directions the export documents, to check a file's frame_axes against the
// rule grid_impostor.frag rederives them by
function frame_direction(i, j, frames, hemi) {
    const ex = ((i + 0.5) / frames) * 2 - 1, ey = ((j + 0.5) / frames) * 2 - 1;
    let d;
    if (hemi) {
        const a = 0.5 * (ex + ey), b = 0.5 * (ey - ex);
        d = new THREE.Vector3(a, 1 - Math.abs(a) - Math.abs(b), b);
    } else {
        d = new THREE.Vector3(ex, 1 - Math.abs(ex) - Math.abs(ey), ey);
        if (d.y < 0) {
            const x = (1 - Math.abs(d.z)) * (d.x >= 0 ? 1 : -1), z = (1 - Math.abs(d.x)) * (d.z >= 0 ? 1 : -1);
            d.x = x;
            d.z = z;
        }
    }
    return d.normalize();
}

function check_frame_axes(extras) {
    const axes = extras.frame_axes;
    if (!Array.isArray(axes)) return null;
    let worst = 0;
    for (let j = 0; j < extras.frames; ++j)
        for (let i = 0; i < extras.frames; ++i) {
            const a = axes[j * extras.frames + i];
            if (!a || a.length !== 9) continue;
            const d = frame_direction(i, j, extras.frames, extras.layout === 'hemi-octahedral');
            worst = Math.max(worst, Math.abs(d.x - a[6]), Math.abs(d.y - a[7]), Math.abs(d.z - a[8]));
        }
    if (worst > 1e-3) console.warn(`grid impostor: frame_axes differ from the octahedral rule by ${worst}`);
    return worst;
}

// data textures as the shaders decode them: no sRGB decode by the sampler, no mips (level 0 is read)
function as_codes(texture) {
    texture.colorSpace = THREE.NoColorSpace;
    texture.generateMipmaps = false;
    texture.minFilter = THREE.LinearFilter;
    texture.magFilter = THREE.LinearFilter;
    texture.flipY = false;
    texture.needsUpdate = true;
    return texture;
}

// what the test reports of a colour map: a transcoded KTX2 (its three format: the GPU block format
// the Basis transcoder chose) or an image
function texture_kind(texture) {
    return texture.isCompressedTexture ? `ktx2 (three format ${texture.format})` : 'image';
}

// the camera and light in a mesh's object space, before each draw (uniforms eye_object,
// forward_object, orthographic, clip_from_object, to_light_object)
function track_camera(mesh, material) {
    mesh.onBeforeRender = (renderer, scene, camera) => {
        const u = material.uniforms;
        const object_from_world = mesh.matrixWorld.clone().invert();
        u.eye_object.value.setFromMatrixPosition(camera.matrixWorld).applyMatrix4(object_from_world);
        u.forward_object.value.set(0, 0, -1).transformDirection(camera.matrixWorld).transformDirection(object_from_world);
        u.orthographic.value = camera.isOrthographicCamera ? 1 : 0;
        u.clip_from_object.value.multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse).multiply(mesh.matrixWorld);
        u.to_light_object.value.copy(k_light_view).transformDirection(camera.matrixWorld).transformDirection(object_from_world);
        material.uniformsNeedUpdate = true;
    };
}

const camera_uniforms = () => ({
    eye_object: { value: new THREE.Vector3() },
    forward_object: { value: new THREE.Vector3(0, 0, -1) },
    orthographic: { value: 0 },
    clip_from_object: { value: new THREE.Matrix4() },
    to_light_object: { value: new THREE.Vector3(0, 0, 1) },
    light_terms: { value: k_light_terms },
});

// The PNG image of glTF texture `index` decoded to 16-bit codes (8-bit ones scaled by 257): the
// browser's own decoder gives WebGL 8 bits of a 16-bit PNG, which would move the billboards' depths
// by up to half an 8-bit code. The chunk walk and unfiltering are png.mjs's (shared with
// tools/ktx2.mjs); inflate is the browser's (DecompressionStream, zlib format). Returns { data
// (Uint16Array, RGBA), width, height, bits }.
async function decode_png_codes(parser, index) {
    const image = parser.json.images[parser.json.textures[index].source];
    let bytes;
    if (image.bufferView !== undefined) bytes = new Uint8Array(await parser.getDependency('bufferView', image.bufferView));
    else bytes = new Uint8Array(await (await fetch(new URL(image.uri, new URL(parser.options.path || '', location.href)))).arrayBuffer());
    try {
        const png = parse_png(bytes);
        const inflated = new Uint8Array(await new Response(new Blob(png.idat).stream().pipeThrough(new DecompressionStream('deflate'))).arrayBuffer());
        return { data: expand_rgba16(png, unfilter_png(png, inflated)), width: png.width, height: png.height, bits: png.bits };
    } catch (error) {
        throw new Error(`texture ${index}: ${error.message}`);
    }
}

// The alpha channel of the top-left width x height texels of an image texture (the export pads its
// maps to multiples of 4; null: not readable here, e.g. a transcoded KTX2).
function texture_alpha(texture, width, height) {
    const image = texture.image;
    if (texture.isCompressedTexture || !image || !(image.width >= width && image.height >= height)) return null;
    const canvas = new OffscreenCanvas(width, height);
    const context = canvas.getContext('2d', { willReadFrequently: true });
    context.drawImage(image, 0, 0);
    const rgba = context.getImageData(0, 0, width, height).data;
    const alpha = new Uint8Array(width * height);
    for (let i = 0; i < alpha.length; ++i) alpha[i] = rgba[4 * i + 3];
    return alpha;
}

// The min/max depth pyramid billboard.frag skips empty space with (standin builds the same at load
// time, src/reps/enhanced_billboards/acceleration.cpp): level 0 is each covered texel's depth and
// those of its covered neighbours that a link might join (the widest the link rule allows, so the
// ranges hold the renderer's, which the exact normals decide: a superset only costs a closer look),
// level k the union over cells of 2^k texels; all levels stacked in one RG32F texture, widened by
// one depth code. Depths are the decoded codes (decode_png_codes); without a readable colour map
// (a transcoded KTX2) every texel counts as covered.
function billboard_pyramid(extras, color, codes) {
    const width = extras.width, height = extras.height;
    const depth = new Float32Array(width * height);
    for (let j = 0; j < height; ++j)
        for (let i = 0; i < width; ++i) depth[j * width + i] = codes.data[4 * (j * codes.width + i) + 3] / 65535;
    const coverage = texture_alpha(color, width, height);
    const levels = Math.max(1, Math.min(8, Math.floor(Math.log2(Math.max(width, height)))));
    const cell = 1 << levels;
    const padded_w = Math.ceil(width / cell) * cell, padded_h = Math.ceil(height / cell) * cell;
    const quantum = codes.bits === 16 ? 1 / 65535 : 1 / 255;
    const widest = (1.5 * 8 + 0.5) * (extras.texel_size / extras.depth_range) + 3 * quantum;
    const covered = (i, j) => i >= 0 && j >= 0 && i < width && j < height && (!coverage || coverage[j * width + i] > 0);
    // level 0: per texel range
    let w = padded_w, h = padded_h;
    let lo = new Float32Array(w * h).fill(2), hi = new Float32Array(w * h).fill(-1);
    for (let j = 0; j < height; ++j)
        for (let i = 0; i < width; ++i) {
            if (!covered(i, j)) continue;
            const d = depth[j * width + i];
            let a = d, b = d;
            for (const [di, dj] of [[1, 0], [-1, 0], [0, 1], [0, -1]]) {
                if (!covered(i + di, j + dj)) continue;
                const e = depth[(j + dj) * width + i + di];
                if (Math.abs(e - d) <= widest) {
                    a = Math.min(a, e);
                    b = Math.max(b, e);
                }
            }
            lo[j * w + i] = a - quantum;
            hi[j * w + i] = b + quantum;
        }
    // levels 1..levels, stacked: level k's rows from rows[k]
    const rows = [0];
    const stacked = [];
    let row = 0;
    for (let k = 1; k <= levels; ++k) {
        const nw = w / 2, nh = h / 2;
        const nlo = new Float32Array(nw * nh), nhi = new Float32Array(nw * nh);
        for (let j = 0; j < nh; ++j)
            for (let i = 0; i < nw; ++i) {
                const at = [(2 * j) * w + 2 * i, (2 * j) * w + 2 * i + 1, (2 * j + 1) * w + 2 * i, (2 * j + 1) * w + 2 * i + 1];
                nlo[j * nw + i] = Math.min(...at.map((x) => lo[x]));
                nhi[j * nw + i] = Math.max(...at.map((x) => hi[x]));
            }
        rows.push(row);
        stacked.push({ lo: nlo, hi: nhi, w: nw, h: nh, row });
        row += nh;
        [w, h, lo, hi] = [nw, nh, nlo, nhi];
    }
    const tw = padded_w / 2;
    const data = new Float32Array(tw * row * 2);
    for (const l of stacked)
        for (let j = 0; j < l.h; ++j)
            for (let i = 0; i < l.w; ++i) {
                data[2 * ((l.row + j) * tw + i)] = l.lo[j * l.w + i];
                data[2 * ((l.row + j) * tw + i) + 1] = l.hi[j * l.w + i];
            }
    const texture = new THREE.DataTexture(data, tw, row, THREE.RGFormat, THREE.FloatType);
    texture.needsUpdate = true;
    return { texture, levels, rows };
}

// a `billboard` node: its box drawn by billboard.{vert,frag} (the ray cast through its height field)
async function billboard(node, extras, parser, shaders) {
    const color = as_codes((await parser.getDependency('texture', extras.color_texture)).clone());
    const codes = await decode_png_codes(parser, extras.normal_depth_texture);
    if (codes.width < extras.width || codes.height < extras.height)
        throw new Error(`billboard: normal + depth map ${codes.width}x${codes.height} smaller than the billboard ${extras.width}x${extras.height}`);
    const normal_depth = new THREE.DataTexture(codes.data, codes.width, codes.height, THREE.RGBAIntegerFormat, THREE.UnsignedShortType);
    normal_depth.internalFormat = 'RGBA16UI';
    normal_depth.needsUpdate = true;
    (window.standin.info.billboard_color_textures ||= []).push(texture_kind(color));
    (window.standin.info.billboard_depth_bits ||= []).push(codes.bits);
    const pyramid = billboard_pyramid(extras, color, codes);
    (window.standin.info.billboard_pyramid_levels ||= []).push(pyramid.levels);
    const rows = [...pyramid.rows, ...Array(9).fill(0)].slice(0, 9);
    const material = new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader: shaders['billboard.vert'],
        fragmentShader: shaders['billboard.frag'],
        side: THREE.BackSide,
        uniforms: {
            color_map: { value: color },
            normal_depth_map: { value: normal_depth },
            origin: { value: new THREE.Vector3().fromArray(extras.origin) },
            axis_u: { value: new THREE.Vector3().fromArray(extras.axis_u) },
            axis_v: { value: new THREE.Vector3().fromArray(extras.axis_v) },
            direction: { value: new THREE.Vector3().fromArray(extras.direction) },
            texel_size: { value: extras.texel_size },
            depth_range: { value: extras.depth_range },
            size_texels: { value: new THREE.Vector2(extras.width, extras.height) },
            depth_quantum: { value: codes.bits === 16 ? 1 / 65535 : 1 / 255 },
            pyramid: { value: pyramid.texture },
            levels: { value: pyramid.levels },
            mark_near_misses: { value: coarse_fill() === 'near-misses' ? 1 : 0 },
            pyramid_rows: { value: rows },
            ...camera_uniforms(),
        },
    });
    const mesh = node.isMesh ? node : node.children.find((c) => c.isMesh);
    if (!mesh) throw new Error('billboard node without a mesh');
    // every fragment that is not discarded (a hit, or with coarse=near-misses a near miss: alpha
    // 0, which the blending leaves invisible) sets the stencil bit, whatever its depth
    material.blending = THREE.CustomBlending;
    material.blendSrc = THREE.SrcAlphaFactor;
    material.blendDst = THREE.OneMinusSrcAlphaFactor;
    material.blendSrcAlpha = THREE.OneFactor;
    material.blendDstAlpha = THREE.OneMinusSrcAlphaFactor;
    material.stencilWrite = true;
    material.stencilFunc = THREE.AlwaysStencilFunc;
    material.stencilRef = k_near_stencil;
    material.stencilWriteMask = k_near_stencil;
    material.stencilZPass = THREE.ReplaceStencilOp;
    material.stencilZFail = THREE.ReplaceStencilOp;
    mesh.material = material;
    mesh.renderOrder = -1; // before the coarse mesh, which reads the stencil
    track_camera(mesh, material);
}

// The stencil bit of pixels where a billboard ray hit (and with coarse=near-misses, where one came
// near a surface and missed). standin's renderer fills every pixel without a front hit with the
// coarse mesh (src/reps/enhanced_billboards/shaders/coarse.frag, --coarse-fill empty): here the
// pixels without the bit. With coarse=near-misses, only the pixels with it (standin's
// --coarse-fill near-misses), depth-tested, so it may also cover a billboard hit behind which it
// lies nearer, which standin's never does; coarse=all draws it everywhere, depth-tested.
const k_near_stencil = 1;
function coarse_fill() {
    const fill = params.get('coarse');
    return fill === 'near-misses' || fill === 'all' ? fill : 'empty';
}
function coarse_mesh(node) {
    if (coarse_fill() === 'all') return;
    node.traverse((m) => {
        if (!m.isMesh) return;
        m.material.stencilWrite = true;
        m.material.stencilFunc = coarse_fill() === 'near-misses' ? THREE.EqualStencilFunc : THREE.NotEqualStencilFunc;
        m.material.stencilRef = k_near_stencil;
        m.material.stencilFuncMask = k_near_stencil;
        m.material.stencilWriteMask = 0;
    });
}

// A grid-impostor material (grid_impostor.{vert,frag}); `hull`: for the atlas hull's own vertices
// instead of the camera-facing square.
async function grid_impostor_material(extras, parser, shaders, hull) {
    if (extras.projection && extras.projection !== 'ortho')
        throw new Error(`grid impostor: projection "${extras.projection}" is not supported (ortho only)`);
    const color = (await parser.getDependency('texture', extras.color_texture)).clone();
    const has_nd = extras.normal_depth_texture !== undefined && extras.normal_depth_texture !== null;
    const normal_depth = has_nd ? (await parser.getDependency('texture', extras.normal_depth_texture)).clone() : null;
    for (const t of [color, normal_depth]) if (t) as_codes(t);
    window.standin.info.color_texture = texture_kind(color);
    return new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader: shaders['grid_impostor.vert'],
        fragmentShader: shaders['grid_impostor.frag'],
        defines: hull ? { HULL: 1 } : {},
        side: hull ? THREE.BackSide : THREE.DoubleSide,
        uniforms: {
            color_atlas: { value: color },
            normal_depth_atlas: { value: normal_depth || color },
            has_normal_depth: { value: has_nd ? 1 : 0 },
            lit_color: { value: extras.color === 'lit' ? 1 : 0 },
            frames: { value: extras.frames },
            hemi: { value: extras.layout === 'hemi-octahedral' ? 1 : 0 },
            center: { value: new THREE.Vector3().fromArray(extras.center) },
            radius: { value: extras.radius },
            half_extent: { value: extras.half_extent },
            depth_near: { value: extras.depth_near },
            depth_scale: { value: extras.depth_scale },
            alpha_tested: { value: extras.alpha_tested ? 1 : 0 }, // absent in exports before it: solid
            ...camera_uniforms(),
            blend_frames: { value: number('blend', 3) === 1 ? 1 : 3 },
            // the most texels the walk crosses per frame (a ray crosses at most 2 sin(angle between
            // frames) of a frame's side: about a third of it between neighbouring frames)
            steps: { value: Math.max(1, Math.min(1024, number('steps', 1024))) },
        },
    });
}

// a `grid-impostor` node: a camera-facing square placed by the vertex stage, replacing the node's
// front-facing quad (which is for plain glTF viewers)
async function grid_impostor(node, extras, parser, shaders) {
    const material = await grid_impostor_material(extras, parser, shaders, false);
    const mesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
    mesh.frustumCulled = false; // the vertex stage places the quad
    track_camera(mesh, material);
    window.standin.info.frame_axes_error = check_frame_axes(extras);
    return mesh;
}

// a `grid-impostor-hull` node: its own mesh (the atlas hull) drawn with the impostor shaders
async function grid_impostor_hull(node, extras, parser, shaders) {
    const material = await grid_impostor_material(extras, parser, shaders, true);
    const mesh = node.isMesh ? node : node.children.find((c) => c.isMesh);
    if (!mesh) throw new Error('grid-impostor-hull node without a mesh');
    mesh.material = material;
    track_camera(mesh, material);
    window.standin.info.frame_axes_error = check_frame_axes(extras);
    window.standin.info.hull_triangles = mesh.geometry.index ? mesh.geometry.index.count / 3 : 0;
}

async function load_standin(url, shaders) {
    const gltf = await gltf_loader().loadAsync(url);
    const root = gltf.scene;
    let root_extras = null;
    const impostors = [];
    const hulls = [];
    const billboards = [];
    const coarse_meshes = [];
    const roles = [];
    root.traverse((node) => {
        const extras = node.userData && node.userData.standin;
        if (!extras) return;
        if (extras.representation) root_extras = extras;
        if (extras.role) roles.push(extras.role);
        if (extras.role === 'grid-impostor') impostors.push({ node, extras });
        if (extras.role === 'grid-impostor-hull') hulls.push({ node, extras });
        if (extras.role === 'billboard') billboards.push({ node, extras });
        if (extras.role === 'coarse-mesh') coarse_meshes.push(node);
    });
    use_mesh_materials(root, shaders);
    if (params.get('billboards') !== 'plain') {
        for (const { node, extras } of billboards) await billboard(node, extras, gltf.parser, shaders);
        for (const node of coarse_meshes) coarse_mesh(node);
    }
    // the impostor on the atlas hull when the file has one (far fewer pixels than the quad), else
    // on the camera-facing quad; the quad node itself is for plain glTF viewers
    const on_hull = hulls.length > 0 && params.get('proxy') !== 'quad';
    window.standin.info.impostor_proxy = impostors.length ? (on_hull ? 'hull' : 'quad') : null;
    for (const { node, extras } of hulls) {
        if (on_hull) await grid_impostor_hull(node, extras, gltf.parser, shaders);
        else node.visible = false;
    }
    for (const { node, extras } of impostors) {
        if (on_hull) {
            node.visible = false;
            continue;
        }
        const mesh = await grid_impostor(node, extras, gltf.parser, shaders);
        node.parent.add(mesh);
        mesh.position.copy(node.position);
        mesh.quaternion.copy(node.quaternion);
        mesh.scale.copy(node.scale);
        node.visible = false; // the front-facing quad is for plain glTF viewers
    }
    window.standin.info.representation = root_extras ? root_extras.representation : null;
    window.standin.info.roles = roles;
    return { object: root, extras: root_extras, impostors };
}

// standin's orbit camera (src/core/camera.cpp orbit_camera)
function orbit_camera(sphere, aspect) {
    const az = THREE.MathUtils.degToRad(number('azimuth', 0));
    const el = THREE.MathUtils.degToRad(number('elevation', 0));
    const distance_rel = number('distance', 1);
    const fov = number('fov', 40);
    const ortho = params.get('ortho') === '1';
    const r = Math.max(sphere.radius, 1e-12);
    const dir = new THREE.Vector3(Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az));
    let camera, eye_distance;
    if (ortho) {
        eye_distance = 3 * r;
        const hh = r * distance_rel, hw = hh * aspect;
        camera = new THREE.OrthographicCamera(-hw, hw, hh, -hh, eye_distance - 1.05 * r, eye_distance + 1.05 * r);
    } else {
        eye_distance = (r / Math.sin(THREE.MathUtils.degToRad(fov) * 0.5)) * distance_rel;
        camera = new THREE.PerspectiveCamera(fov, aspect, Math.max(eye_distance - 1.05 * r, 0.01 * r), eye_distance + 1.05 * r);
    }
    camera.up.set(0, 1, 0);
    if (Math.abs(dir.y) > 0.999) camera.up.set(0, 0, dir.y > 0 ? -1 : 1);
    camera.position.copy(sphere.center).addScaledVector(dir, eye_distance);
    camera.lookAt(sphere.center);
    camera.updateMatrixWorld();
    return camera;
}

function sphere_of_box(box) {
    // standin's bounding sphere: the box's centre, half its diagonal (include/standin/mesh.h)
    const center = box.getCenter(new THREE.Vector3());
    return new THREE.Sphere(center, 0.5 * box.getSize(new THREE.Vector3()).length());
}

function update_light(scene, camera) {
    const to_light = k_light_view.clone().transformDirection(camera.matrixWorld);
    scene.traverse((node) => {
        if (node.isMesh && node.material.uniforms && node.material.uniforms.to_light_world)
            node.material.uniforms.to_light_world.value.copy(to_light);
    });
}

async function main() {
    const model_url = params.get('model');
    const standin_url = params.get('standin');
    if (!model_url && !standin_url) throw new Error('give ?model=URL and/or ?standin=URL (README.md)');
    let view = params.get('view') || (model_url && standin_url ? 'both' : model_url ? 'model' : 'standin');
    if (!['both', 'model', 'standin'].includes(view)) throw new Error(`view=${view}: use both, model or standin`);
    const still = params.get('still') === '1';

    const size = params.get('size');
    let width = window.innerWidth, height = window.innerHeight;
    if (size) {
        const m = /^(\d+)x(\d+)$/.exec(size);
        if (!m) throw new Error(`size=${size}: use WxH`);
        width = Number(m[1]);
        height = Number(m[2]);
    }
    const canvas = document.getElementById('view');
    const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: true, preserveDrawingBuffer: true,
        stencil: true }); // billboards' coarse mesh (billboard())
    renderer.setPixelRatio(size ? 1 : window.devicePixelRatio);
    renderer.setSize(width, height, true);
    renderer.setClearColor(0x000000, 0);
    renderer.autoClear = false;
    ktx2_loader = new KTX2Loader()
        .setTranscoderPath(new URL('node_modules/three/examples/jsm/libs/basis/', import.meta.url).href)
        .detectSupport(renderer);

    const shaders = await load_shaders();
    const [model, standin] = await Promise.all([
        model_url ? load_model(model_url) : null,
        standin_url ? load_standin(standin_url, shaders) : null,
    ]);
    if (model) use_mesh_materials(model.object, shaders);

    // frame both as `standin render` frames them: the model's box (a package is framed by its
    // source's bounds, which are the model's); without the model, the impostor's sphere or the
    // stand-in's own box
    let sphere;
    if (model) sphere = sphere_of_box(new THREE.Box3().setFromObject(model.object));
    else if (standin.impostors.length)
        sphere = new THREE.Sphere(new THREE.Vector3().fromArray(standin.impostors[0].extras.center), standin.impostors[0].extras.radius);
    else sphere = sphere_of_box(new THREE.Box3().setFromObject(standin.object));
    window.standin.info.sphere = { center: sphere.center.toArray(), radius: sphere.radius };


    const halves = [];
    if (view !== 'standin' && model) halves.push(new THREE.Scene().add(model.object));
    if (view !== 'model' && standin) halves.push(new THREE.Scene().add(standin.object));
    const split = halves.length;
    const camera = orbit_camera(sphere, width / split / height);
    let controls = null;
    if (!still) {
        controls = new OrbitControls(camera, canvas);
        controls.target.copy(sphere.center);
        controls.autoRotate = true;
        controls.autoRotateSpeed = number('spin', 10) / 6; // OrbitControls: 2 = 30 s a turn (12 deg/s)
        controls.update();
    }

    const draw = () => {
        renderer.setScissorTest(false);
        renderer.clear();
        renderer.setScissorTest(true);
        const w = renderer.domElement.width / renderer.getPixelRatio() / split;
        halves.forEach((scene, k) => {
            renderer.setViewport(k * w, 0, w, height);
            renderer.setScissor(k * w, 0, w, height);
            update_light(scene, camera);
            renderer.render(scene, camera);
        });
    };
    if (still) {
        draw();
        window.standin.ready = true;
        return;
    }
    renderer.setAnimationLoop(() => {
        controls.update();
        draw();
    });
    window.standin.ready = true;
}

// The covered pixels of the drawing against standin's picture of the same camera (a PNG with a
// transparent background): intersection over union of alpha >= 0.5, for the browser test.
window.standin.silhouette_iou = async (png_url) => {
    const canvas = document.getElementById('view');
    const gl = canvas.getContext('webgl2');
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const pixels = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    const blob = await (await fetch(png_url)).blob();
    const bitmap = await createImageBitmap(blob, { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
    if (bitmap.width !== w || bitmap.height !== h)
        throw new Error(`${png_url} is ${bitmap.width}x${bitmap.height}, the drawing ${w}x${h}`);
    const context = new OffscreenCanvas(w, h).getContext('2d');
    context.drawImage(bitmap, 0, 0);
    const truth = context.getImageData(0, 0, w, h).data;
    let both = 0, either = 0, ours = 0, theirs = 0;
    for (let y = 0; y < h; ++y)
        for (let x = 0; x < w; ++x) {
            const a = pixels[((h - 1 - y) * w + x) * 4 + 3] >= 128; // readPixels rows run bottom-up
            const b = truth[(y * w + x) * 4 + 3] >= 128;
            if (a) ++ours;
            if (b) ++theirs;
            if (a && b) ++both;
            if (a || b) ++either;
        }
    return { iou: either ? both / either : 1, web_pixels: ours, standin_pixels: theirs, width: w, height: h };
};

main().catch((error) => {
    console.error(error);
    window.standin.error = String(error && error.message ? error.message : error);
    const banner = document.getElementById('error');
    if (banner) banner.textContent = window.standin.error;
});
