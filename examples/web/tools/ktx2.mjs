// Rewrites the colour textures of a .glb written by `standin export` as KTX2 with Basis Universal
// supercompression (glTF extension KHR_texture_basisu), so that an engine uploads them as GPU
// block-compressed textures (BCn, ETC, ASTC: whatever the GPU has, transcoded at load time) instead
// of RGBA8. Debian packages no Basis encoder (no basisu, no KTX-Software toktx); the npm package
// ktx2-encoder ships Binomial's basis_universal encoder compiled to WebAssembly with a Node entry,
// which is what this uses. Sources: Khronos, "KHR_texture_basisu" (glTF extension, ratified 2021)
// and "KTX File Format Specification 2.0"; Binomial (R. Geldreich), Basis Universal (2019-).
//   node tools/ktx2.mjs IN.glb OUT.glb [--etc1s | --uastc] [--quality Q] [--keep-png]
//
// Steps:
//   1. Read the GLB (header, JSON chunk, BIN chunk); refuse anything but one embedded buffer.
//   2. Colour textures: those a material uses as baseColorTexture and those a node's
//      extras.standin names as color_texture. Data textures (extras normal_depth_texture: linear
//      normal and depth codes, 16-bit for billboards) stay PNG, bit-exact: a lossy block code moves
//      the depth the impostor and billboard shaders intersect, and Basis has no 16-bit LDR mode.
//      A texture in both sets (none today) also stays PNG.
//   3. Decode each colour PNG (RGBA8, as standin writes them) and encode it: ETC1S (default;
//      smallest files, lossy; quality --quality 1..255, default 128) or UASTC LDR 4x4 (--uastc;
//      larger, near-BC7 quality; Zstandard supercompressed), sRGB transfer function in the DFD
//      (the glTF baseColorTexture convention), perceptual metrics, full mip chain (the file's
//      sampler asks for trilinear mips). Rows are kept top first, as glTF and KHR_texture_basisu
//      require (KTXorientation "rd").
//   4. Write a new GLB in which each converted image is the KTX2 (mimeType image/ktx2) and its
//      texture names it through extensions.KHR_texture_basisu.source. By default the extension is
//      required and the PNG is dropped (texture.source removed): the point is the GPU footprint
//      and, for detailed atlases, the download, and three.js and the Khronos validator accept it; --keep-png keeps the PNG as texture.source
//      (the fallback for loaders without Basis; the extension then is only "used").
//   5. Everything else (nodes, extras with their texture indices, accessors, the other images) is
//      copied unchanged; texture indices do not move.
//
// Departures: KHR_texture_basisu wants base dimensions that are multiples of 4; a colour texture
// whose size is not is left PNG (reported on stderr), since padding it would move its UVs. Output is
// written to a temporary name, then renamed. Bad input is one line naming the file, exit status 2.
import { closeSync, fsyncSync, openSync, readFileSync, renameSync, rmSync, writeSync } from 'node:fs';
import { basename, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { inflateSync } from 'node:zlib';
import { parse_png, unfilter_png, expand_rgba8 } from '../png.mjs';

const k_usage = 'usage: node tools/ktx2.mjs IN.glb OUT.glb [--etc1s | --uastc] [--quality 1..255] [--keep-png] [--quiet]';
const k_glb_magic = 0x46546c67, k_json_chunk = 0x4e4f534a, k_bin_chunk = 0x004e4942;

export class InputError extends Error {}
const fail = (what, message) => { throw new InputError(`${what}: ${message}`); };

// ---- PNG (8-bit, non-interlaced; standin writes RGBA8 colour maps): ../png.mjs, inflated here ----
export function decode_png(bytes, what) {
    let png, raw;
    try { png = parse_png(bytes); } catch (e) { fail(what, e.message); }
    if (png.bits !== 8) fail(what, `PNG is ${png.bits}-bit: only 8-bit colour maps are converted`);
    let inflated;
    try { inflated = inflateSync(Buffer.concat(png.idat)); } catch (e) { fail(what, `PNG data does not inflate (${e.message})`); }
    try { raw = unfilter_png(png, inflated); } catch (e) { fail(what, e.message); }
    return { width: png.width, height: png.height, data: expand_rgba8(png, raw) };
}

// ---- GLB ----
export function read_glb(bytes, what) {
    if (bytes.length < 20) fail(what, 'shorter than a GLB header');
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    if (view.getUint32(0, true) !== k_glb_magic) fail(what, 'not a binary glTF (no "glTF" magic)');
    if (view.getUint32(4, true) !== 2) fail(what, `GLB version ${view.getUint32(4, true)}, expected 2`);
    if (view.getUint32(8, true) !== bytes.length) fail(what, `GLB length field ${view.getUint32(8, true)} differs from the file size ${bytes.length}`);
    let json = null, bin = null;
    for (let at = 12; at < bytes.length;) {
        if (at + 8 > bytes.length) fail(what, 'truncated GLB chunk header');
        const length = view.getUint32(at, true), type = view.getUint32(at + 4, true);
        if (at + 8 + length > bytes.length) fail(what, 'GLB chunk runs past the end of the file');
        const body = bytes.subarray(at + 8, at + 8 + length);
        if (type === k_json_chunk && !json) {
            try { json = JSON.parse(new TextDecoder('utf-8', { fatal: true }).decode(body)); } catch (e) { fail(what, `JSON chunk: ${e.message}`); }
        } else if (type === k_bin_chunk && !bin) bin = body;
        at += 8 + length;
    }
    if (!json || typeof json !== 'object') fail(what, 'no JSON chunk');
    return { json, bin: bin || new Uint8Array(0) };
}

function pad4(n) { return (n + 3) & ~3; }

export function write_glb(json, bin) {
    const text = Buffer.from(JSON.stringify(json), 'utf8');
    const json_length = pad4(text.length), bin_length = pad4(bin.length);
    const total = 12 + 8 + json_length + (bin.length ? 8 + bin_length : 0);
    const out = Buffer.alloc(total);
    out.writeUInt32LE(k_glb_magic, 0);
    out.writeUInt32LE(2, 4);
    out.writeUInt32LE(total, 8);
    out.writeUInt32LE(json_length, 12);
    out.writeUInt32LE(k_json_chunk, 16);
    text.copy(out, 20);
    out.fill(0x20, 20 + text.length, 20 + json_length); // JSON pads with spaces
    if (bin.length) {
        const at = 20 + json_length;
        out.writeUInt32LE(bin_length, at);
        out.writeUInt32LE(k_bin_chunk, at + 4);
        Buffer.from(bin.buffer, bin.byteOffset, bin.length).copy(out, at + 8);
    }
    return out;
}

// What KHR_texture_basisu asks of a KTX2 (the Khronos validator, npm gltf-validator 2.0.0-dev.3.10,
// does not know the extension and only warns that it cannot read the image): Basis payload
// (vkFormat 0; ETC1S in BasisLZ, or UASTC in none/Zstandard), one 2D image (no depth, layers,
// faces), base size the PNG's and a multiple of 4, the full mip chain (the sampler minifies with
// mips), BT.709 primaries and the sRGB transfer of a baseColorTexture, alpha not premultiplied, the
// DFD channels the extension lists, orientation "rd" and swizzle "rgba" if stated.
// Returns the first rule broken, or null.
export function check_ktx2(bytes, width, height, uastc) {
    const id = [0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a];
    if (bytes.length < 80 || id.some((v, i) => bytes[i] !== v)) return 'not a KTX2 file';
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const u32 = (at) => view.getUint32(at, true);
    const [vk_format, , w, h, depth, layers, faces, levels, scheme] = [12, 16, 20, 24, 28, 32, 36, 40, 44].map(u32);
    if (vk_format !== 0) return `vkFormat ${vk_format}, not 0 (Basis)`;
    if (w !== width || h !== height) return `size ${w}x${h}, the PNG's is ${width}x${height}`;
    if (w % 4 || h % 4) return `size ${w}x${h} is not a multiple of 4`;
    if (depth !== 0 || layers !== 0 || faces !== 1) return `depth ${depth}, layers ${layers}, faces ${faces}: not one 2D image`;
    const full = Math.floor(Math.log2(Math.max(w, h))) + 1;
    if (levels !== full) return `${levels} mip levels, the full chain is ${full}`;
    if (uastc ? scheme !== 0 && scheme !== 2 : scheme !== 1) return `supercompression scheme ${scheme} for ${uastc ? 'UASTC' : 'ETC1S'}`;
    const dfd = u32(48), dfd_length = u32(52), kvd = u32(56), kvd_length = u32(60);
    if (dfd + dfd_length > bytes.length || kvd + kvd_length > bytes.length || dfd_length < 28) return 'descriptor or key/value data beyond the file';
    const model = bytes[dfd + 12], primaries = bytes[dfd + 13], transfer = bytes[dfd + 14];
    if (model !== (uastc ? 166 : 163)) return `DFD colour model ${model}, not ${uastc ? 'UASTC (166)' : 'ETC1S (163)'}`;
    if (primaries !== 1) return `DFD primaries ${primaries}, not BT.709 (1)`;
    if (transfer !== 2) return `DFD transfer ${transfer}, not sRGB (2)`;
    if (bytes[dfd + 15] & 1) return 'DFD flags premultiplied alpha';
    // samples: 16 bytes each after the 24-byte block header; the channel id is the top 4 bits of
    // byte 3 of each (ETC1S: RGB 0 and AAA 15 for RGBA; UASTC: one sample, RGB 0 or RGBA 3)
    const samples = (view.getUint16(dfd + 10, true) - 24) / 16;
    const channels = Array.from({ length: Math.max(0, samples) }, (_, k) => bytes[dfd + 4 + 24 + 16 * k + 3] & 15);
    const ok = uastc ? channels.length === 1 && (channels[0] === 0 || channels[0] === 3)
        : (channels.length === 1 && channels[0] === 0) || (channels.length === 2 && channels[0] === 0 && channels[1] === 15);
    if (!ok) return `DFD channels [${channels}] are not ${uastc ? 'UASTC RGB or RGBA' : 'ETC1S RGB (+ AAA)'}`;
    for (let at = kvd; at + 4 <= kvd + kvd_length;) {
        const length = u32(at);
        const pair = bytes.subarray(at + 4, at + 4 + length);
        const zero = pair.indexOf(0);
        const key = new TextDecoder().decode(pair.subarray(0, zero < 0 ? pair.length : zero));
        const value = new TextDecoder().decode(pair.subarray(zero + 1)).replace(/\0+$/, '');
        if (key === 'KTXorientation' && value !== 'rd') return `KTXorientation "${value}", not "rd"`;
        if (key === 'KTXswizzle' && value !== 'rgba') return `KTXswizzle "${value}", not "rgba"`;
        at += 4 + pad4(length);
    }
    return null;
}

// colour and data textures by index, from materials and standin's node extras
export function classify_textures(json) {
    const colour = new Set(), data = new Set();
    for (const m of json.materials || []) {
        const t = m && m.pbrMetallicRoughness && m.pbrMetallicRoughness.baseColorTexture;
        if (t && Number.isInteger(t.index)) colour.add(t.index);
    }
    for (const n of [...(json.nodes || []), ...(json.scenes || [])]) {
        const e = n && n.extras && n.extras.standin;
        if (!e) continue;
        if (Number.isInteger(e.color_texture)) colour.add(e.color_texture);
        if (Number.isInteger(e.normal_depth_texture)) data.add(e.normal_depth_texture);
    }
    for (const t of data) colour.delete(t);
    return { colour: [...colour].sort((a, b) => a - b), data };
}

// options: { uastc, quality, keep_png, log }
export async function convert_glb(bytes, what, options) {
    const { json, bin } = read_glb(bytes, what);
    const images = json.images || [], textures = json.textures || [], views = json.bufferViews || [];
    if ((json.buffers || []).length > 1 || (json.buffers || []).some((b) => b.uri !== undefined))
        fail(what, 'only a GLB with one embedded buffer is converted');
    for (const [k, v] of views.entries())
        if (!v || (v.buffer || 0) !== 0 || !Number.isInteger(v.byteOffset || 0) || !Number.isInteger(v.byteLength) ||
            (v.byteOffset || 0) < 0 || v.byteLength < 0 || (v.byteOffset || 0) + v.byteLength > bin.length)
            fail(what, `bufferView ${k} lies outside the binary chunk`);
    if ((json.extensionsUsed || []).includes('KHR_texture_basisu')) fail(what, 'already uses KHR_texture_basisu');
    const { colour } = classify_textures(json);

    // the encoder's WebAssembly prints its progress through a console.log bound when it starts:
    // start it with console.log silenced, so that only this tool's summary reaches stdout
    const { NodeBasisEncoder } = await import('ktx2-encoder');
    const encoder = new NodeBasisEncoder();
    const saved_log = console.log;
    console.log = () => {};
    try { await encoder.init(); } finally { console.log = saved_log; }
    const encoded = new Map(); // image index -> KTX2 bytes
    let png_bytes = 0, ktx2_bytes = 0; // of the converted images
    const converted = [];
    for (const t of colour) {
        const texture = textures[t];
        if (!texture) fail(what, `texture ${t} (named by a material or extras) does not exist`);
        const image = images[texture.source];
        if (!image) fail(what, `texture ${t} has no image`);
        if (image.mimeType !== 'image/png' || !Number.isInteger(image.bufferView) || !views[image.bufferView])
            fail(what, `image ${texture.source} is not a PNG in the binary chunk`);
        if (encoded.has(texture.source)) { converted.push(t); continue; }
        const v = views[image.bufferView];
        const png = bin.subarray(v.byteOffset || 0, (v.byteOffset || 0) + v.byteLength);
        const decoded = decode_png(png, `${what}: image ${texture.source}`);
        if (decoded.width % 4 || decoded.height % 4) {
            options.log(`ktx2: ${what}: texture ${t} is ${decoded.width}x${decoded.height}, not a multiple of 4: kept as PNG`);
            continue;
        }
        const ktx2 = await encoder.encode(png, {
            enableDebug: false,
            imageDecoder: async () => decoded,
            isUASTC: options.uastc,
            isKTX2File: true,
            isSetKTX2SRGBTransferFunc: true,
            isPerceptual: true,
            generateMipmap: true,
            isYFlip: false,
            qualityLevel: options.uastc ? undefined : options.quality,
            compressionLevel: options.uastc ? undefined : 2,
            needSupercompression: options.uastc ? true : undefined,
            uastcLDRQualityLevel: options.uastc ? 2 : undefined,
        });
        const broken = check_ktx2(ktx2, decoded.width, decoded.height, options.uastc);
        if (broken) throw new Error(`${what}: texture ${t}: the encoder wrote a KTX2 that KHR_texture_basisu refuses: ${broken}`);
        encoded.set(texture.source, ktx2);
        png_bytes += png.length;
        ktx2_bytes += ktx2.length;
        converted.push(t);
    }

    // the new binary chunk: every view in order, converted images replaced, 4-byte aligned (as the
    // export writes it, so accessors stay aligned)
    const out_images = images.map((i) => ({ ...i }));
    const ktx2_image = new Map(); // old image index -> image index of its KTX2
    const pieces = views.map((v) => bin.subarray(v.byteOffset || 0, (v.byteOffset || 0) + v.byteLength));
    const out_views = views.map((v) => ({ ...v }));
    for (const [source, ktx2] of encoded) {
        if (options.keep_png) {
            out_views.push({ buffer: 0, byteLength: ktx2.length });
            pieces.push(ktx2);
            out_images.push({ ...(images[source].name ? { name: images[source].name } : {}), bufferView: out_views.length - 1, mimeType: 'image/ktx2' });
            ktx2_image.set(source, out_images.length - 1);
        } else {
            pieces[images[source].bufferView] = ktx2;
            out_images[source].mimeType = 'image/ktx2';
            ktx2_image.set(source, source);
        }
    }
    let size = 0;
    for (const [k, p] of pieces.entries()) {
        out_views[k].byteOffset = size;
        out_views[k].byteLength = p.length;
        size = pad4(size + p.length);
    }
    const out_bin = new Uint8Array(size);
    for (const [k, p] of pieces.entries()) out_bin.set(p, out_views[k].byteOffset);

    const out = { ...json, images: out_images, bufferViews: out_views };
    if (json.buffers && json.buffers.length) out.buffers = [{ ...json.buffers[0], byteLength: out_bin.length }];
    out.textures = textures.map((t) => {
        if (!ktx2_image.has(t.source)) return t;
        const copy = { ...t, extensions: { ...(t.extensions || {}), KHR_texture_basisu: { source: ktx2_image.get(t.source) } } };
        if (!options.keep_png) delete copy.source;
        return copy;
    });
    if (encoded.size) {
        out.extensionsUsed = [...(json.extensionsUsed || []), 'KHR_texture_basisu'];
        if (!options.keep_png) out.extensionsRequired = [...(json.extensionsRequired || []), 'KHR_texture_basisu'];
    }
    return { glb: write_glb(out, out_bin), converted, kept: textures.length - converted.length, png_bytes, ktx2_bytes };
}

function parse_args(argv) {
    const o = { input: null, output: null, uastc: false, quality: 128, keep_png: false, quiet: false };
    const positional = [];
    for (let i = 0; i < argv.length; ++i) {
        const a = argv[i];
        if (a === '--uastc') o.uastc = true;
        else if (a === '--etc1s') o.uastc = false;
        else if (a === '--keep-png') o.keep_png = true;
        else if (a === '--quiet' || a === '-q') o.quiet = true;
        else if (a === '--quality') {
            o.quality = Number(argv[++i]);
            if (!Number.isInteger(o.quality) || o.quality < 1 || o.quality > 255) throw new InputError(`ktx2: --quality ${argv[i]}: an integer in 1..255`);
        } else if (a.startsWith('-')) throw new InputError(`ktx2: unknown option ${a} (${k_usage})`);
        else positional.push(a);
    }
    if (positional.length !== 2) throw new InputError(`ktx2: give IN.glb and OUT.glb (${k_usage})`);
    [o.input, o.output] = positional;
    if (!o.output.toLowerCase().endsWith('.glb')) throw new InputError(`ktx2: ${o.output}: the output must be a .glb`);
    return o;
}

async function main() {
    let o, tmp = null;
    try {
        o = parse_args(process.argv.slice(2));
        let bytes;
        try { bytes = new Uint8Array(readFileSync(o.input)); } catch (e) { fail(o.input, `cannot read (${e.code || e.message})`); }
        const log = o.quiet ? () => {} : (line) => console.error(line);
        const result = await convert_glb(bytes, o.input, { ...o, log });
        tmp = `${o.output}.tmp-${process.pid}`;
        try {
            const fd = openSync(tmp, 'w');
            writeSync(fd, result.glb);
            fsyncSync(fd);
            closeSync(fd);
            renameSync(tmp, o.output);
        } catch (e) { fail(o.output, `cannot write (${e.code || e.message})`); }
        tmp = null;
        if (!o.quiet)
            console.log(`${basename(o.output)}: ${result.converted.length} colour texture(s) as KTX2 ${o.uastc ? 'UASTC' : 'ETC1S'}` +
                `${o.keep_png ? ' (PNG kept as fallback)' : ''} (${result.png_bytes} bytes of PNG -> ${result.ktx2_bytes} of KTX2), ` +
                `${result.kept} texture(s) kept as PNG; file ${bytes.length} -> ${result.glb.length} bytes`);
    } catch (e) {
        if (tmp) rmSync(tmp, { force: true });
        console.error(e instanceof InputError ? e.message : `ktx2: ${e && e.message ? e.message : e}`);
        process.exit(2);
    }
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) await main();
