// File readers of the web preview: PNG (heightmaps and `relief bake --format png` maps) and KTX2
// (`relief bake --format ktx2`). Both are small hand-written parsers of our own, not general ones:
// the browser's image decoder gives 8-bit sRGB-managed pixels, and a 16-bit cone map or height
// must reach the shader as the exact codes the bake wrote (docs/maps.md). The KTX2 reader takes
// only what src/relief/io/map_ktx2.cpp writes: uncompressed (supercompression 0), 2D, the
// VkFormats R8/R8G8/R8G8B8A8_UNORM, R16..._UNORM, R32..._SFLOAT, layers or mip levels, no faces.

const kPngSignature = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];
const kKtx2Signature = [0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a];

function startsWith(bytes, magic) {
    return bytes.length >= magic.length && magic.every((b, k) => bytes[k] === b);
}

export function isPng(bytes) { return startsWith(bytes, kPngSignature); }
export function isKtx2(bytes) { return startsWith(bytes, kKtx2Signature); }

async function inflate(bytes) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Uint8Array(await new Response(stream).arrayBuffer());
}

function paeth(a, b, c) {
    const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// { width, height, channels, bits, samples (Uint8Array or Uint16Array, row 0 = the file's first
// row), text: {key: value} from tEXt chunks }. Non-interlaced grey, grey+alpha, RGB, RGBA at 8 or
// 16 bits, and 8-bit palette images (expanded to RGB).
export async function decodePng(bytes, name) {
    if (!isPng(bytes)) throw new Error(`${name}: not a PNG file`);
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    let width = 0, height = 0, bits = 0, colorType = 0, interlace = 0, palette = null;
    const idat = [], text = {};
    for (let at = 8; at + 8 <= bytes.length;) {
        const length = view.getUint32(at);
        const type = String.fromCharCode(...bytes.subarray(at + 4, at + 8));
        const data = bytes.subarray(at + 8, at + 8 + length);
        if (type === 'IHDR') {
            width = view.getUint32(at + 8);
            height = view.getUint32(at + 12);
            bits = data[8];
            colorType = data[9];
            interlace = data[12];
        } else if (type === 'PLTE') {
            palette = data;
        } else if (type === 'IDAT') {
            idat.push(data);
        } else if (type === 'tEXt') {
            const zero = data.indexOf(0);
            text[new TextDecoder('latin1').decode(data.subarray(0, zero))] =
                new TextDecoder('latin1').decode(data.subarray(zero + 1));
        } else if (type === 'IEND') {
            break;
        }
        at += 12 + length;
    }
    const channelsOf = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4};
    if (!(colorType in channelsOf) || interlace !== 0 || !(bits === 8 || bits === 16))
        throw new Error(`${name}: PNG colour type ${colorType}, ${bits} bits, interlace ` +
                        `${interlace}: only non-interlaced 8/16-bit images are read here`);
    const channels = channelsOf[colorType];
    const joined = new Uint8Array(idat.reduce((n, d) => n + d.length, 0));
    idat.reduce((at, d) => (joined.set(d, at), at + d.length), 0);
    const raw = await inflate(joined);
    const bpp = channels * bits / 8, stride = width * bpp;
    if (raw.length < height * (stride + 1)) throw new Error(`${name}: truncated image data`);
    const rows = new Uint8Array(height * stride);
    for (let y = 0; y < height; ++y) {
        const filter = raw[y * (stride + 1)];
        const src = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
        const out = rows.subarray(y * stride, (y + 1) * stride);
        const up = y > 0 ? rows.subarray((y - 1) * stride, y * stride) : new Uint8Array(stride);
        for (let i = 0; i < stride; ++i) {
            const a = i >= bpp ? out[i - bpp] : 0, b = up[i], c = i >= bpp ? up[i - bpp] : 0;
            const predict = [0, a, b, (a + b) >> 1, paeth(a, b, c)][filter];
            if (predict === undefined) throw new Error(`${name}: bad PNG filter ${filter}`);
            out[i] = (src[i] + predict) & 0xff;
        }
    }
    let samples;
    if (bits === 16) {
        samples = new Uint16Array(width * height * channels);
        for (let k = 0; k < samples.length; ++k) samples[k] = rows[2 * k] << 8 | rows[2 * k + 1];
    } else {
        samples = rows;
    }
    if (colorType === 3) {
        if (!palette) throw new Error(`${name}: palette image without PLTE`);
        const rgb = new Uint8Array(width * height * 3);
        for (let k = 0; k < width * height; ++k) rgb.set(palette.subarray(3 * samples[k], 3 * samples[k] + 3), 3 * k);
        return {width, height, channels: 3, bits, samples: rgb, text};
    }
    return {width, height, channels, bits, samples, text};
}

// The heights of a PNG as relief reads them (src/relief/io/read_common.cpp): code / (2^bits − 1),
// the luminance 0.2126 R + 0.7152 G + 0.0722 B of a colour image, row 0 = the first row.
export function heightsFromPng(png) {
    const scale = 1 / ((1 << png.bits) - 1), n = png.width * png.height, c = png.channels;
    const h = new Float32Array(n);
    for (let k = 0; k < n; ++k) {
        const p = png.samples.subarray(k * c, k * c + c);
        h[k] = c >= 3 ? 0.2126 * p[0] * scale + 0.7152 * p[1] * scale + 0.0722 * p[2] * scale
                      : p[0] * scale;
    }
    return {width: png.width, height: png.height, samples: h};
}

// relief.arrays "NAME:WxHxC,..." as [{name, width, height, channels}].
function parseArrays(text) {
    return text.split(',').filter(Boolean).map(item => {
        const [name, shape] = [item.slice(0, item.lastIndexOf(':')), item.slice(item.lastIndexOf(':') + 1)];
        const [width, height, channels] = shape.split('x').map(Number);
        return {name, width, height, channels};
    });
}

// relief.parameters "k=v;k=v" as {k: v}.
function parseParameters(text) {
    const out = {};
    for (const item of (text || '').split(/[;,]/).filter(Boolean)) {
        const eq = item.indexOf('=');
        out[item.slice(0, eq)] = item.slice(eq + 1);
    }
    return out;
}

function mapsFromKeys(keys, name) {
    for (const key of ['relief.technique', 'relief.arrays', 'relief.storage', 'relief.source.depth'])
        if (!(key in keys)) throw new Error(`${name}: no ${key}: not a map written by relief bake`);
    return {
        technique: keys['relief.technique'],
        parameters: parseParameters(keys['relief.parameters']),
        depth: Number(keys['relief.source.depth']),
        edge: keys['relief.source.edge'] || 'clamp',
        size: keys['relief.source.size'],
        storage: keys['relief.storage'],
        shapes: parseArrays(keys['relief.arrays']),
        arrays: {},  // name → {width, height, channels, data: Float32Array}
    };
}

// A baked map PNG: one array; UNORM codes decoded to the bake's floats, integer codes as values.
export async function mapFromPng(bytes, name) {
    const png = await decodePng(bytes, name);
    const maps = mapsFromKeys(png.text, name);
    const [shape] = maps.shapes;
    if (maps.shapes.length !== 1 || shape.width !== png.width || shape.height !== png.height ||
        shape.channels !== png.channels)
        throw new Error(`${name}: relief.arrays ${png.text['relief.arrays']} does not match the ` +
                        `${png.width}x${png.height}x${png.channels} image`);
    const integer = maps.storage.startsWith('int');
    const scale = integer ? 1 : 1 / ((1 << png.bits) - 1);
    maps.arrays[shape.name] = {...shape, data: Float32Array.from(png.samples, v => v * scale)};
    return maps;
}

const kVkFormats = {  // VkFormat → [channels, bytes per channel, float]
    9: [1, 1, false], 16: [2, 1, false], 37: [4, 1, false],
    70: [1, 2, false], 77: [2, 2, false], 91: [4, 2, false],
    100: [1, 4, true], 103: [2, 4, true], 109: [4, 4, true],
};

// A baked map KTX2: its arrays as layers (in relief.arrays order) or mip levels (a max pyramid:
// level L is the array of index L; the base was padded to powers of two, so each level's array is
// its top-left corner at the size relief.arrays gives).
export function mapFromKtx2(bytes, name) {
    if (!isKtx2(bytes)) throw new Error(`${name}: not a KTX2 file`);
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const u32 = at => view.getUint32(at, true);
    const vkFormat = u32(12), width = u32(20), height = u32(24), layers = u32(32), faces = u32(36);
    const levels = Math.max(1, u32(40)), scheme = u32(44);
    const format = kVkFormats[vkFormat];
    if (!format || scheme !== 0 || faces !== 1 || u32(28) !== 0)
        throw new Error(`${name}: VkFormat ${vkFormat}, supercompression ${scheme}, ${faces} faces: ` +
                        'not an uncompressed 2D map from relief bake');
    const kvdOffset = u32(56), kvdLength = u32(60), keys = {};
    for (let at = kvdOffset; at < kvdOffset + kvdLength;) {
        const length = u32(at);
        const pair = bytes.subarray(at + 4, at + 4 + length);
        const zero = pair.indexOf(0);
        const decoder = new TextDecoder();
        keys[decoder.decode(pair.subarray(0, zero))] =
            decoder.decode(pair.subarray(zero + 1, pair[length - 1] === 0 ? length - 1 : length));
        at += 4 + length + ((4 - length % 4) % 4);
    }
    const maps = mapsFromKeys(keys, name);
    const [channels, bytesPer, isFloat] = format;
    const texel = channels * bytesPer, scale = isFloat ? 1 : 1 / (2 ** (8 * bytesPer) - 1);
    const read = (at) => isFloat ? view.getFloat32(at, true)
                       : bytesPer === 2 ? view.getUint16(at, true) * scale : bytes[at] * scale;
    const mips = levels > 1;
    if (maps.shapes.length !== (mips ? levels : Math.max(1, layers)))
        throw new Error(`${name}: ${maps.shapes.length} arrays for ${levels} levels, ${layers} layers`);
    maps.shapes.forEach((shape, index) => {
        const level = mips ? index : 0, layer = mips ? 0 : index;
        const offset = Number(view.getBigUint64(80 + 24 * level, true));
        const lw = Math.max(1, width >> level), lh = Math.max(1, height >> level);
        const base = offset + layer * lw * lh * texel;
        const data = new Float32Array(shape.width * shape.height * shape.channels);
        for (let y = 0; y < shape.height; ++y)
            for (let x = 0; x < shape.width; ++x)
                for (let c = 0; c < shape.channels; ++c)
                    data[(y * shape.width + x) * shape.channels + c] =
                        read(base + (y * lw + x) * texel + c * bytesPer);
        maps.arrays[shape.name] = {...shape, data};
    });
    return maps;
}

export async function readMap(bytes, name) {
    if (isPng(bytes)) return mapFromPng(bytes, name);
    if (isKtx2(bytes)) return mapFromKtx2(bytes, name);
    throw new Error(`${name}: neither PNG nor KTX2 (relief bake --format png|ktx2)`);
}
