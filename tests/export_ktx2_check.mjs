// Checks a .glb that examples/web/tools/ktx2.mjs converted against the export it came from
// (tests/export_validator.sh runs it; the Khronos validator cannot read KTX2 images itself):
//   - the data textures (extras normal_depth_texture) are the same PNG bytes: bit-exact;
//   - every colour texture is either the same PNG, or a KTX2 through KHR_texture_basisu that passes
//     the extension's rules (check_ktx2), with the base size of the PNG it replaced;
//   - at least MIN colour textures were converted; the extension is required exactly when the PNG
//     was dropped;
//   - everything but images, textures, bufferViews, buffers and the extension lists is unchanged,
//     so the texture indices in extras still name the same textures.
// Usage: node export_ktx2_check.mjs KTX2_TOOL.mjs ORIGINAL.glb CONVERTED.glb MIN_CONVERTED
// Exit 0 pass, 1 fail (one line per problem).
import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const [tool, original_path, converted_path, min_text] = process.argv.slice(2);
const { read_glb, classify_textures, check_ktx2, decode_png } = await import(pathToFileURL(tool).href);
const a = read_glb(new Uint8Array(readFileSync(original_path)), original_path);
const b = read_glb(new Uint8Array(readFileSync(converted_path)), converted_path);
const problems = [];
const image_bytes = (glb, index) => {
    const image = glb.json.images[index];
    const view = glb.json.bufferViews[image.bufferView];
    return { mime: image.mimeType, bytes: glb.bin.subarray(view.byteOffset || 0, (view.byteOffset || 0) + view.byteLength) };
};
const same = (x, y) => x.length === y.length && x.every((v, i) => v === y[i]);

for (const key of Object.keys({ ...a.json, ...b.json })) {
    if (['images', 'textures', 'bufferViews', 'buffers', 'extensionsUsed', 'extensionsRequired'].includes(key)) continue;
    if (JSON.stringify(a.json[key]) !== JSON.stringify(b.json[key])) problems.push(`"${key}" changed`);
}
if ((a.json.textures || []).length !== (b.json.textures || []).length) problems.push('the number of textures changed');
const { colour, data } = classify_textures(a.json);
for (const t of data) {
    const x = image_bytes(a, a.json.textures[t].source), y = image_bytes(b, b.json.textures[t].source);
    if (y.mime !== 'image/png' || !same(x.bytes, y.bytes)) problems.push(`data texture ${t} is not the same PNG`);
}
let converted = 0, fallback = 0;
for (const t of colour) {
    const before = image_bytes(a, a.json.textures[t].source);
    const texture = b.json.textures[t];
    const basisu = texture.extensions && texture.extensions.KHR_texture_basisu;
    if (!basisu) {
        if (!same(before.bytes, image_bytes(b, texture.source).bytes)) problems.push(`colour texture ${t} left PNG but changed`);
        continue;
    }
    ++converted;
    const ktx2 = image_bytes(b, basisu.source);
    if (ktx2.mime !== 'image/ktx2') problems.push(`colour texture ${t}: KHR_texture_basisu source is ${ktx2.mime}`);
    const { width, height } = decode_png(before.bytes, `${original_path} texture ${t}`);
    const uastc = ktx2.bytes[44] !== 1; // supercompression BasisLZ is ETC1S's
    const broken = check_ktx2(ktx2.bytes, width, height, uastc);
    if (broken) problems.push(`colour texture ${t}: ${broken}`);
    if (texture.source !== undefined) {
        ++fallback;
        if (!same(before.bytes, image_bytes(b, texture.source).bytes)) problems.push(`colour texture ${t}: its PNG fallback changed`);
    }
}
const required = (b.json.extensionsRequired || []).includes('KHR_texture_basisu');
if (converted < Number(min_text)) problems.push(`${converted} colour textures converted, expected at least ${min_text}`);
if (converted && !(b.json.extensionsUsed || []).includes('KHR_texture_basisu')) problems.push('KHR_texture_basisu not in extensionsUsed');
if (converted && required !== (fallback === 0)) problems.push(`KHR_texture_basisu ${required ? 'required' : 'not required'} with ${fallback} PNG fallbacks`);
for (const p of problems) console.log(`FAIL ${converted_path}: ${p}`);
if (!problems.length) console.log(`${converted_path}: ${converted} colour texture(s) as KTX2${fallback ? ' (PNG fallback kept)' : ''}, data textures bit-exact`);
process.exit(problems.length ? 1 : 0);
