// ctest ktx2_parse: relief's hand-written KTX2 map files read by ktx-parse (pinned in
// package.json, installed into the build tree by ktx2_parse_setup with npm ci). Bakes maps with
// the relief under test, then checks each file's header, level count, Data Format Descriptor, key/
// value data and level bytes: UNORM codes against the PNG export of the same bake (decoded here,
// independently of relief), the safety distances against their PNG integer codes, and the max
// pyramid's mip levels against its invariant (each node the max of its 2×2 children).
// Usage: node check_ktx2.mjs RELIEF_EXECUTABLE WORK_DIR
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { inflateSync } from 'node:zlib';
import { read } from 'ktx-parse';

const [relief, work] = process.argv.slice(2);
mkdirSync(work, { recursive: true });
let failures = 0;
function check(condition, what) {
    if (!condition) {
        console.error(`FAIL: ${what}`);
        ++failures;
    }
}

function bake(args, out) {
    execFileSync(relief, ['bake', ...args, '-o', join(work, out), '--deterministic'], { stdio: 'pipe' });
}

const text = (v) => (typeof v === 'string' ? v : new TextDecoder().decode(v)).replace(/\0+$/, '');

// A PNG's samples (8 or 16 bits, big-endian in the file), unfiltered: zlib and the five filters.
function decodePng(path) {
    const b = readFileSync(path);
    let at = 8, idat = [], w = 0, h = 0, depth = 0, type = 0;
    while (at < b.length) {
        const length = b.readUInt32BE(at), kind = b.toString('latin1', at + 4, at + 8);
        const data = b.subarray(at + 8, at + 8 + length);
        if (kind === 'IHDR') [w, h, depth, type] = [data.readUInt32BE(0), data.readUInt32BE(4), data[8], data[9]];
        if (kind === 'IDAT') idat.push(data);
        at += 12 + length;
    }
    const channels = { 0: 1, 4: 2, 2: 3, 6: 4 }[type];
    const bpp = channels * depth / 8, stride = w * bpp;
    const raw = inflateSync(Buffer.concat(idat)), out = Buffer.alloc(stride * h);
    for (let y = 0; y < h; ++y) {
        const filter = raw[y * (stride + 1)], row = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
        for (let x = 0; x < stride; ++x) {
            const a = x >= bpp ? out[y * stride + x - bpp] : 0, up = y ? out[(y - 1) * stride + x] : 0;
            const c = x >= bpp && y ? out[(y - 1) * stride + x - bpp] : 0;
            const p = a + up - c, pa = Math.abs(p - a), pb = Math.abs(p - up), pc = Math.abs(p - c);
            const predictor = [0, a, up, (a + up) >> 1, pa <= pb && pa <= pc ? a : pb <= pc ? up : c][filter];
            out[y * stride + x] = (row[x] + predictor) & 0xff;
        }
    }
    const samples = [];
    for (let k = 0; k < w * h * channels; ++k) samples.push(depth === 16 ? out.readUInt16BE(2 * k) : out[k]);
    return { w, h, depth, channels, samples };
}

// One KTX2 file: what ktx-parse reads, checked against the expected layout.
function parse(name, want) {
    const c = read(new Uint8Array(readFileSync(join(work, name))));
    const is = (got, expected, what) => check(got === expected, `${name}: ${what} is ${got}, expected ${expected}`);
    is(c.vkFormat, want.vkFormat, 'vkFormat');
    is(c.typeSize, want.bits / 8, 'typeSize');
    is(c.pixelWidth, want.width, 'pixelWidth');
    is(c.pixelHeight, want.height, 'pixelHeight');
    is(c.pixelDepth, 0, 'pixelDepth');
    is(c.layerCount, want.layers, 'layerCount');
    is(c.faceCount, 1, 'faceCount');
    is(c.levels.length, want.levels, 'level count');
    is(c.supercompressionScheme, 0, 'supercompressionScheme');
    const d = c.dataFormatDescriptor[0];
    is(d.vendorId, 0, 'DFD vendorId');
    is(d.descriptorType, 0, 'DFD descriptorType');
    is(d.versionNumber, 2, 'DFD versionNumber');
    is(d.colorModel, 1, 'DFD colorModel (RGBSDA)');
    is(d.transferFunction, 1, 'DFD transferFunction (linear)');
    is(d.bytesPlane[0], want.bits / 8 * want.components, 'DFD bytesPlane0');
    is(d.samples.length, want.components, 'DFD sample count (from descriptorBlockSize)');
    d.samples.forEach((s, k) => {
        is(s.bitOffset, k * want.bits, `sample ${k} bitOffset`);
        is(s.bitLength, want.bits - 1, `sample ${k} bitLength`);
        is(s.channelType & 0x0f, [0, 1, 2, 15][k], `sample ${k} channel id`);
        is(s.channelType & 0xf0, want.float ? 0xc0 : 0, `sample ${k} qualifiers`);
        is(s.sampleUpper >>> 0, want.float ? 0x3f800000 : 2 ** want.bits - 1, `sample ${k} sampleUpper`);
    });
    is(text(c.keyValue.KTXorientation), 'rd', 'KTXorientation');
    check(text(c.keyValue.KTXwriter).startsWith('relief'), `${name}: KTXwriter`);
    is(text(c.keyValue['relief.technique']), want.technique, 'relief.technique');
    is(text(c.keyValue['relief.storage']), want.storage, 'relief.storage');
    for (const key of ['relief.version', 'relief.parameters', 'relief.source.hash', 'relief.source.size',
                       'relief.source.edge', 'relief.source.depth', 'relief.parts', 'relief.checksums'])
        check(c.keyValue[key] !== undefined, `${name}: ${key} missing`);
    const arrays = text(c.keyValue['relief.arrays']).split(',').map((e) => {
        const [n, dims] = e.split(':');
        const [w, h, ch] = dims.split('x').map(Number);
        return { n, w, h, ch };
    });
    is(arrays.length, Math.max(want.levels, want.layers), 'arrays listed');
    c.levels.forEach((l, i) => {
        const bytes = Math.max(1, want.width >> i) * Math.max(1, want.height >> i) *
                      want.bits / 8 * want.components * Math.max(1, want.layers);
        is(l.levelData.byteLength, bytes, `level ${i} bytes`);
        is(l.uncompressedByteLength, bytes, `level ${i} uncompressedByteLength`);
    });
    return { c, arrays };
}

function levelValues(c, i, want) {
    const data = c.levels[i].levelData, view = new DataView(data.buffer, data.byteOffset, data.byteLength);
    const n = data.byteLength / (want.bits / 8), values = [];
    for (let k = 0; k < n; ++k)
        values.push(want.float ? view.getFloat32(4 * k, true) : want.bits === 16 ? view.getUint16(2 * k, true) : view.getUint8(k));
    return values;
}

// Cones at 8 and 16 bits: the KTX2 codes are the PNG's, code for code.
for (const bits of [8, 16]) {
    bake(['gen:fbm:48x40:3', '--maps', 'cone', '--param', `bits=${bits}`], `cone${bits}.ktx2`);
    bake(['gen:fbm:48x40:3', '--maps', 'cone', '--param', `bits=${bits}`], `cone${bits}.png`);
    const want = { vkFormat: bits === 8 ? 16 : 77, bits, components: 2, width: 48, height: 40, layers: 0, levels: 1,
                   technique: 'cone', storage: `unit${bits}`, float: false };
    const { c } = parse(`cone${bits}.ktx2`, want);
    const png = decodePng(join(work, `cone${bits}.png`));
    check(png.depth === bits && png.channels === 2, `cone${bits}.png: ${png.depth} bits, ${png.channels} channels`);
    const codes = levelValues(c, 0, want);
    check(codes.length === png.samples.length && codes.every((v, k) => v === png.samples[k]),
          `cone${bits}.ktx2: codes differ from the PNG export's`);
}

// 32-bit cones: floats, the ratio channel in [0, 1].
{
    bake(['gen:fbm:48x40:3', '--maps', 'cone'], 'cone32.ktx2');
    const want = { vkFormat: 103, bits: 32, components: 2, width: 48, height: 40, layers: 0, levels: 1,
                   technique: 'cone', storage: 'float32', float: true };
    const { c } = parse('cone32.ktx2', want);
    const v = levelValues(c, 0, want);
    check(v.every((x, k) => k % 2 === 0 ? x >= 0 : x >= 0 && x <= 1), 'cone32.ktx2: values out of range');
}

// Safety distances: floats in the KTX2, equal to the PNG's integer codes.
{
    bake(['gen:fbm:48x40:3', '--maps', 'safety-sd'], 'sd.ktx2');
    bake(['gen:fbm:48x40:3', '--maps', 'safety-sd'], 'sd.png');
    const want = { vkFormat: 109, bits: 32, components: 4, width: 48, height: 40, layers: 0, levels: 1,
                   technique: 'safety-sd', storage: 'float32', float: true };
    const { c } = parse('sd.ktx2', want);
    const png = decodePng(join(work, 'sd.png'));
    const v = levelValues(c, 0, want);
    check(png.channels === 4 && v.length === png.samples.length && v.every((x, k) => x === png.samples[k]),
          'sd.ktx2: distances differ from the PNG export\'s codes');
}

// Cylinder-cone maps: four classes as layers, 3 channels padded to RGBA with 0.
{
    bake(['gen:fbm:48x40:3', '--maps', 'safety-cc'], 'cc.ktx2');
    const want = { vkFormat: 109, bits: 32, components: 4, width: 48, height: 40, layers: 4, levels: 1,
                   technique: 'safety-cc', storage: 'float32', float: true };
    const { c, arrays } = parse('cc.ktx2', want);
    check(arrays.map((a) => a.n).join() === 'ccx+,ccx-,ccy+,ccy-', `cc.ktx2: layers ${arrays.map((a) => a.n)}`);
    const v = levelValues(c, 0, want);
    check(v.every((x, k) => k % 4 !== 3 || x === 0), 'cc.ktx2: padding channel not 0');
    check(v.every((x, k) => k % 4 !== 0 || Number.isInteger(x)), 'cc.ktx2: radii not whole');
}

// Max pyramids (clamp: 49×41 cells, repeat: 48×40) as mip levels of a power-of-two base: each
// node is the max of its children, the padding is 0.
for (const [edge, cw, ch] of [['clamp', 49, 41], ['repeat', 48, 40]]) {
    const name = `pyramid-${edge}.ktx2`;
    bake(['gen:fbm:48x40:3', '--edge', edge, '--maps', 'quadtree'], name);
    const levels = Math.ceil(Math.log2(Math.max(cw, ch))) + 1;
    const want = { vkFormat: 100, bits: 32, components: 1, width: 64, height: 64, layers: 0, levels,
                   technique: 'quadtree', storage: 'float32', float: true };
    const { c, arrays } = parse(name, want);
    const values = c.levels.map((_, i) => levelValues(c, i, want));
    arrays.forEach((a, i) => {
        check(a.n === `level${i}` && a.w === Math.ceil(cw / 2 ** i) && a.h === Math.ceil(ch / 2 ** i),
              `${name}: array ${i} is ${a.n} ${a.w}x${a.h}`);
        const stride = Math.max(1, 64 >> i);
        for (let y = 0; y < stride; ++y)
            for (let x = 0; x < stride; ++x) {
                const v = values[i][y * stride + x];
                if (x >= a.w || y >= a.h) {
                    check(v === 0, `${name}: level ${i} padding (${x}, ${y}) is ${v}`);
                } else if (i > 0) {
                    const f = arrays[i - 1], fs = Math.max(1, 64 >> (i - 1));
                    let m = -Infinity;
                    for (const [dx, dy] of [[0, 0], [1, 0], [0, 1], [1, 1]])
                        m = Math.max(m, values[i - 1][Math.min(2 * y + dy, f.h - 1) * fs + Math.min(2 * x + dx, f.w - 1)]);
                    check(v === m, `${name}: level ${i} node (${x}, ${y}) is ${v}, its children's max ${m}`);
                }
            }
    });
}

if (failures) {
    console.error(`${failures} check(s) failed`);
    process.exit(1);
}
console.log('ktx2_parse: every KTX2 map file read by ktx-parse as written');
