// PNG decoding shared by the viewer (main.js, in the browser) and tools/ktx2.mjs (in Node): the
// chunk walk and the row unfiltering of the PNG specification (W3C PNG, 2nd edition 2003, §5, §9),
// for the non-interlaced 8- and 16-bit images standin writes. Inflate is the caller's, because
// the two environments have different ones (the browser's DecompressionStream is asynchronous,
// Node's zlib.inflateSync is not); everything else lives here once.
//
// Why by hand: the browser's own decoder gives WebGL 8 bits of a 16-bit PNG (the billboards' depth
// codes need 16), and Node has no PNG decoder; the npm ones would be a dependency for 100 lines.
//
//   const png = parse_png(bytes);            // { width, height, bits, channels, colour_type, interlace, idat }
//   const raw = unfilter_png(png, inflated); // the image's bytes, rows packed, big-endian samples
//   const rgba8 = expand_rgba8(png, raw), codes = expand_rgba16(png, raw);
// Errors are plain Errors whose message says what is wrong; callers prefix the file's name.

const k_signature = [137, 80, 78, 71, 13, 10, 26, 10];
const k_channels = { 0: 1, 2: 3, 4: 2, 6: 4 }; // grey, RGB, grey + alpha, RGBA (no palettes)

// The header and the IDAT chunks (still deflated) of PNG file `bytes` (a Uint8Array).
export function parse_png(bytes) {
    if (bytes.length < 8 || k_signature.some((v, i) => bytes[i] !== v)) throw new Error('not a PNG');
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const png = { width: 0, height: 0, bits: 0, channels: 0, colour_type: -1, interlace: 0, idat: [] };
    let header = false;
    for (let at = 8; at + 12 <= bytes.length;) {
        const length = view.getUint32(at);
        const name = String.fromCharCode(...bytes.subarray(at + 4, at + 8));
        if (at + 12 + length > bytes.length) throw new Error(`PNG chunk ${name} runs past the end`);
        const body = bytes.subarray(at + 8, at + 8 + length);
        if (name === 'IHDR') {
            if (length < 13) throw new Error('PNG header chunk is too short');
            png.width = view.getUint32(at + 8);
            png.height = view.getUint32(at + 12);
            png.bits = body[8];
            png.colour_type = body[9];
            png.interlace = body[12];
            png.channels = k_channels[png.colour_type] || 0;
            header = true;
        } else if (name === 'IDAT') png.idat.push(body);
        else if (name === 'IEND') break;
        at += 12 + length;
    }
    if (!header) throw new Error('PNG has no header chunk');
    if (!png.channels || !(png.bits === 8 || png.bits === 16) || png.interlace !== 0)
        throw new Error(`PNG colour type ${png.colour_type}, ${png.bits}-bit${png.interlace ? ', interlaced' : ''}: ` +
                        'only 8- or 16-bit grey, RGB or RGBA without interlacing is read');
    if (!(png.width > 0 && png.height > 0 && png.width <= 16384 && png.height <= 16384))
        throw new Error(`PNG size ${png.width}x${png.height} out of range`);
    return png;
}

function paeth(a, b, c) {
    const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// The image's bytes with the row filters undone: `inflated` is the IDAT data inflated (zlib).
export function unfilter_png(png, inflated) {
    const bpp = (png.channels * png.bits) / 8, stride = png.width * bpp;
    if (inflated.length < (stride + 1) * png.height) throw new Error('PNG data is shorter than its size');
    const raw = new Uint8Array(stride * png.height);
    for (let y = 0; y < png.height; ++y) {
        const filter = inflated[y * (stride + 1)];
        if (filter > 4) throw new Error(`PNG row filter ${filter} is invalid`);
        const line = inflated.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
        const out = y * stride, up = out - stride;
        for (let x = 0; x < stride; ++x) {
            const a = x >= bpp ? raw[out + x - bpp] : 0, b = y > 0 ? raw[up + x] : 0;
            const c = x >= bpp && y > 0 ? raw[up + x - bpp] : 0;
            const p = filter === 0 ? 0 : filter === 1 ? a : filter === 2 ? b : filter === 3 ? (a + b) >> 1 : paeth(a, b, c);
            raw[out + x] = (line[x] + p) & 255;
        }
    }
    return raw;
}

// Sample k (0..channels-1) of pixel i as a 16-bit code (8-bit samples scaled by 257).
function sample16(png, raw, i, k) {
    const bytes = png.bits / 8, at = (i * png.channels + k) * bytes;
    return bytes === 2 ? (raw[at] << 8) | raw[at + 1] : raw[at] * 257;
}

// RGBA per pixel as 16-bit codes (Uint16Array): grey spread to RGB, missing alpha 65535.
export function expand_rgba16(png, raw) {
    const n = png.width * png.height, out = new Uint16Array(n * 4);
    const grey = png.channels <= 2, alpha = png.channels === 2 ? 1 : png.channels === 4 ? 3 : -1;
    for (let i = 0; i < n; ++i) {
        for (let k = 0; k < 3; ++k) out[4 * i + k] = sample16(png, raw, i, grey ? 0 : k);
        out[4 * i + 3] = alpha < 0 ? 65535 : sample16(png, raw, i, alpha);
    }
    return out;
}

// RGBA per pixel as 8-bit values (Uint8Array); 16-bit samples keep their high byte.
export function expand_rgba8(png, raw) {
    const codes = expand_rgba16(png, raw), out = new Uint8Array(codes.length);
    for (let i = 0; i < codes.length; ++i) out[i] = codes[i] >> 8;
    return out;
}
