// The material preview in WebGL2: a heightmap and a baked map (relief bake --format png|ktx2) on
// a built-in mesh, drawn with the engine shader library (shaders/relief/, fetched at run time) in
// GLSL ES 3.00 and the mesh preview's own shaders (src/relief/gl/shaders/preview_*.glsl, the
// ones `relief render --mesh` uses), so a page view matches that command's image of the same
// options. Query parameters (all optional) preset the page, for links and the headless test:
// height, map, color (URLs), mesh, technique, elevation, azimuth, distance, fov, width, height
// as size=WxH, depth-ratio or depth, tiles, shadows=1 (off by default, as in relief render), light-elevation, light-azimuth, ui=0.
import {decodePng, heightsFromPng, readMap} from './formats.js';
import {builtinMesh, directionFromAngles, orbitCamera} from './mesh.js';
import {kTechniques} from './techniques.js';

const query = new URLSearchParams(location.search);
const $ = id => document.getElementById(id);
const state = {
    heights: null, heightName: '', maps: null, mapName: '', color: null,
    mesh: query.get('mesh') || 'sphere',
    technique: query.get('technique') || '',
    view: {elevation: num('elevation', 40.2), azimuth: num('azimuth', 30), distance: num('distance', 1.2), fov: num('fov', 45)},
    light: {elevation: num('light-elevation', 45), azimuth: num('light-azimuth', 135)},
    depthRatio: num('depth-ratio', 0.1), depth: query.has('depth') ? num('depth', 0) : null,
    tiles: num('tiles', 1), shadows: query.get('shadows') === '1', maxSteps: null,  // off, as relief render
};
const [width, height] = (query.get('size') || '800x600').split('x').map(Number);
const canvas = $('view');
canvas.width = width;
canvas.height = height;
const gl = canvas.getContext('webgl2', {antialias: false, preserveDrawingBuffer: true});
let program = null, programKey = '', textures = {}, meshBuffers = null, sources = {};

function num(key, fallback) {
    return query.has(key) ? Number(query.get(key)) : fallback;
}

function status(text, isError = false) {
    $('status').textContent = text;
    document.body.dataset.state = isError ? 'error' : text === 'ready' ? 'ready' : 'busy';
    if (isError) console.warn(text);  // a user's bad file is a message, not a page error
}

// Served by `relief serve` at /shaders/relief/ and /gl/; opened as a file, the repository's own
// folders relative to web/ (a browser may refuse file:// fetches: then serve it).
function sourceUrl(kind, file) {
    const served = location.protocol.startsWith('http');
    const dir = kind === 'library' ? (served ? '/shaders/relief/' : '../shaders/relief/')
                                   : (served ? '/gl/' : '../src/relief/gl/shaders/');
    return new URL(dir + file, location.href);
}

async function source(kind, file) {
    const key = kind + '/' + file;
    if (!(key in sources)) {
        const response = await fetch(sourceUrl(kind, file));
        if (!response.ok) throw new Error(`${file}: HTTP ${response.status}`);
        sources[key] = await response.text();
    }
    return sources[key];
}

// common.glsl, then the row's file after the files its `// requires:` lines name, each once
// (gl/shader_library.cpp's shaderLibraryText).
async function libraryText(file) {
    const ordered = [];
    const addFile = async name => {
        if (ordered.includes(name)) return;
        const text = await source('library', name);
        for (const m of text.matchAll(/\n\/\/ requires: (\S+)/g)) await addFile(m[1]);
        ordered.push(name);
    };
    await addFile('common.glsl');
    await addFile(file);
    return (await Promise.all(ordered.map(n => source('library', n)))).join('\n');
}

const kHeader = '#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n';

function compile(type, text, what) {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS))
        throw new Error(`${what}: ${gl.getShaderInfoLog(s)}`);
    return s;
}

async function buildProgram(row) {
    const samplers = row.samplers.map(([name]) => `uniform sampler2D ${name};\n`).join('');
    const args = row.samplers.map(([name]) => name + ', ').join('');
    const fragment = kHeader + (await libraryText(row.file)) + '\n' + samplers +
        `#define RELIEF_TRACE(uv, v, p) ${row.fn}(${args}uv, v, p)\n` +
        `#define RELIEF_SHADOW(hit, l, p) ${row.fn}Shadow(${args}hit, l, p)\n` +
        (await source('gl', 'preview_fragment.glsl'));
    const vertex = kHeader + (await source('gl', 'preview_vertex.glsl'));
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, vertex, 'preview_vertex.glsl'));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fragment, `${row.file} + preview_fragment.glsl`));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(`link: ${gl.getProgramInfoLog(p)}`);
    return p;
}

const kFloatFormats = [[gl.R32F, gl.RED], [gl.RG32F, gl.RG], [gl.RGB32F, gl.RGB], [gl.RGBA32F, gl.RGBA]];

function floatTexture(array) {
    const t = gl.createTexture();
    const [internal, format] = kFloatFormats[array.channels - 1];
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texStorage2D(gl.TEXTURE_2D, 1, internal, array.width, array.height);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, array.width, array.height, format, gl.FLOAT, array.data);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    return t;
}

// A max pyramid "<stem>0", "<stem>1", ... as the mip levels of one texture, level 0 padded to
// powers of two (mipChainTexture in gl/shader_library.cpp).
function mipChainTexture(maps, first) {
    const stem = first.replace(/\d+$/, ''), start = Number(first.slice(stem.length));
    const levels = [];
    while (maps.arrays[stem + (start + levels.length)]) levels.push(maps.arrays[stem + (start + levels.length)]);
    if (!levels.length) throw new Error(`the map has no array ${first}`);
    const padded = n => 1 << Math.ceil(Math.log2(n));
    const [internal, format] = kFloatFormats[levels[0].channels - 1];
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texStorage2D(gl.TEXTURE_2D, levels.length, internal, padded(levels[0].width), padded(levels[0].height));
    levels.forEach((a, l) => gl.texSubImage2D(gl.TEXTURE_2D, l, 0, 0, a.width, a.height, format, gl.FLOAT, a.data));
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST_MIPMAP_NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAX_LEVEL, levels.length - 1);
    return t;
}

function wrapMode() { return edge() === 'repeat' ? gl.REPEAT : gl.CLAMP_TO_EDGE; }
function edge() { return state.maps ? state.maps.edge : 'clamp'; }
function depth() {
    if (state.maps) return state.maps.depth;  // the depth the map was baked for
    return state.depth ?? state.depthRatio * Math.max(state.heights.width, state.heights.height);
}

// Normals of z = D·h by central differences, edges as the surface (normalTexture in
// preview/mesh_renderer.cpp), with a box-filtered mip chain made here: WebGL2 cannot generate
// mipmaps of a float texture.
function normalTexture() {
    const {width: w, height: h, samples} = state.heights, D = depth(), wrap = edge() === 'repeat';
    const at = (i, j) => {
        i = wrap ? ((i % w) + w) % w : Math.min(Math.max(i, 0), w - 1);
        j = wrap ? ((j % h) + h) % h : Math.min(Math.max(j, 0), h - 1);
        return D * samples[j * w + i];
    };
    let level = new Float32Array(w * h * 4), lw = w, lh = h;
    for (let j = 0; j < h; ++j)
        for (let i = 0; i < w; ++i) {
            const x = -0.5 * (at(i + 1, j) - at(i - 1, j)), y = -0.5 * (at(i, j + 1) - at(i, j - 1));
            const n = Math.hypot(x, y, 1);
            level.set([x / n, y / n, 1 / n, 1], 4 * (j * w + i));
        }
    const levels = [[level, lw, lh]];
    while (lw > 1 || lh > 1) {
        const nw = Math.max(1, lw >> 1), nh = Math.max(1, lh >> 1), next = new Float32Array(nw * nh * 4);
        for (let j = 0; j < nh; ++j)
            for (let i = 0; i < nw; ++i)
                for (let c = 0; c < 4; ++c) {
                    let s = 0;
                    for (const [di, dj] of [[0, 0], [1, 0], [0, 1], [1, 1]])
                        s += level[4 * (Math.min(2 * j + dj, lh - 1) * lw + Math.min(2 * i + di, lw - 1)) + c];
                    next[4 * (j * nw + i) + c] = 0.25 * s;
                }
        levels.push([next, nw, nh]);
        [level, lw, lh] = [next, nw, nh];
    }
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texStorage2D(gl.TEXTURE_2D, levels.length, gl.RGBA16F, w, h);
    levels.forEach(([data, a, b], l) => gl.texSubImage2D(gl.TEXTURE_2D, l, 0, 0, a, b, gl.RGBA, gl.FLOAT, data));
    filtered();
    return t;
}

function filtered() {
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, wrapMode());
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, wrapMode());
}

function colorTexture(image) {
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.SRGB8_ALPHA8, gl.RGBA, gl.UNSIGNED_BYTE, image);
    gl.generateMipmap(gl.TEXTURE_2D);
    filtered();
    return t;
}

function uploadMesh() {
    const mesh = builtinMesh(state.mesh);
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const vb = gl.createBuffer(), ib = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, vb);
    gl.bufferData(gl.ARRAY_BUFFER, mesh.vertices, gl.STATIC_DRAW);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, mesh.indices, gl.STATIC_DRAW);
    [[0, 3, 0], [1, 3, 3], [2, 2, 6], [3, 4, 8], [4, 2, 12]].forEach(([loc, size, at]) => {
        gl.enableVertexAttribArray(loc);
        gl.vertexAttribPointer(loc, size, gl.FLOAT, false, 56, 4 * at);
    });
    gl.bindVertexArray(null);
    meshBuffers = {vao, count: mesh.indices.length};
}

// The rows the loaded map serves (its relief.technique), else those that read heights only.
function usableTechniques() {
    const names = Object.keys(kTechniques);
    if (!state.maps) return names.filter(n => kTechniques[n].samplers.length === 1);
    return names.filter(n => n === state.maps.technique || kTechniques[n].samplers.length === 1);
}

async function rebuild() {
    if (!state.heights) return status('load a heightmap PNG (and a baked map) to start');
    const usable = usableTechniques();
    if (!usable.includes(state.technique))
        state.technique = state.maps && usable.includes(state.maps.technique) ? state.maps.technique : usable[0];
    const select = $('technique');
    select.replaceChildren(...usable.map(n => new Option(n, n, false, n === state.technique)));
    const row = kTechniques[state.technique];
    if (state.maps && state.maps.size !== `${state.heights.width}x${state.heights.height}`)
        throw new Error(`${state.mapName} was baked from a ${state.maps.size} heightmap, ` +
                        `${state.heightName} is ${state.heights.width}x${state.heights.height}`);
    const key = state.technique;
    if (key !== programKey) {
        program = await buildProgram(row);
        programKey = key;
    }
    for (const t of Object.values(textures)) gl.deleteTexture(t);
    textures = {};
    for (const [name, array, mip] of row.samplers) {
        if (!array) textures[name] = floatTexture({...state.heights, channels: 1, data: state.heights.samples});
        else if (mip) textures[name] = mipChainTexture(state.maps, array);
        else if (state.maps.arrays[array]) textures[name] = floatTexture(state.maps.arrays[array]);
        else throw new Error(`${state.mapName}: no array ${array}`);
    }
    textures.normalMap = normalTexture();
    if (state.color) textures.colorMap = colorTexture(state.color);
    if (state.maxSteps === null || !$('max-steps').dataset.row || $('max-steps').dataset.row !== key) {
        state.maxSteps = row.maxSteps;
        $('max-steps').value = row.maxSteps;
        $('max-steps').dataset.row = key;
    }
    uploadMesh();
    draw();
}

function draw() {
    if (!program || !meshBuffers) return;
    const row = kTechniques[state.technique], mp = state.maps ? state.maps.parameters : {};
    const mapParam = (k, fallback) => (k in mp ? Number(mp[k]) : fallback);
    const {eye, clip} = orbitCamera(state.view, width, height);
    gl.viewport(0, 0, width, height);
    gl.clearColor(0.10, 0.11, 0.13, 1);
    gl.clearDepth(1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(program);
    const u = name => gl.getUniformLocation(program, name);
    gl.uniformMatrix4fv(u('clipFromWorld'), false, clip);
    gl.uniform3fv(u('eye'), eye);
    gl.uniform3fv(u('towardsLight'), directionFromAngles(state.light.elevation, state.light.azimuth));
    gl.uniform1i(u('shadows'), state.shadows ? 1 : 0);
    gl.uniform1i(u('hasColor'), state.color ? 1 : 0);
    gl.uniform1f(u('exposure'), 0);
    gl.uniform1f(u('specular'), 0.25);
    gl.uniform1f(u('tiles'), state.tiles);
    gl.uniform1i(u('object'), 1);
    const hs = state.heights.samples;
    let maxH = 0;
    for (let k = 0; k < hs.length; ++k) maxH = Math.max(maxH, hs[k]);
    // setLibraryUniforms / libraryParams (gl/shader_library.cpp).
    const ints = {edge: edge() === 'repeat' ? 1 : 0, maxSteps: state.maxSteps, binarySteps: row.binarySteps,
                  bits: mapParam('bits', 32), sqrtRatio: mapParam('sqrt', 0), ascend: 1,
                  exterior: mapParam('exterior', 0), viewDependent: 0, positiveDistance: 0,
                  isotropic: mapParam('isotropic', 0), variant: state.technique === 'qdm' ? mapParam('variant', 0) : 0};
    const floats = {depth: depth(), midLevel: 1, coneMax: mapParam('cone-max', 1), maxZ: depth() * maxH,
                    maxDistance: state.technique === 'qdm' ? mapParam('max-distance', 0) : 0, phiMax: mapParam('phi-max', 90)};
    gl.uniform2f(u('params.mapSize'), state.heights.width, state.heights.height);
    for (const [k, v] of Object.entries(ints)) gl.uniform1i(u('params.' + k), v);
    for (const [k, v] of Object.entries(floats)) gl.uniform1f(u('params.' + k), v);
    let unit = 0;
    for (const name of [...row.samplers.map(s => s[0]), 'normalMap', 'colorMap']) {
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(gl.TEXTURE_2D, textures[name] || null);
        gl.uniform1i(u(name), unit++);
    }
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.bindVertexArray(meshBuffers.vao);
    gl.drawElements(gl.TRIANGLES, meshBuffers.count, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
    status('ready');
}

async function bytesOf(fileOrUrl) {
    if (typeof fileOrUrl === 'string') {
        const response = await fetch(fileOrUrl);
        if (!response.ok) throw new Error(`${fileOrUrl}: HTTP ${response.status}`);
        return new Uint8Array(await response.arrayBuffer());
    }
    return new Uint8Array(await fileOrUrl.arrayBuffer());
}

const nameOf = f => (typeof f === 'string' ? f.split('/').pop() : f.name);

async function loadHeights(f) {
    state.heights = heightsFromPng(await decodePng(await bytesOf(f), nameOf(f)));
    state.heightName = nameOf(f);
}

async function loadMap(f) {
    state.maps = await readMap(await bytesOf(f), nameOf(f));
    state.mapName = nameOf(f);
    state.technique = state.maps.technique;
}

async function loadColor(f) {
    const blob = typeof f === 'string' ? await (await fetch(f)).blob() : f;
    state.color = await createImageBitmap(blob, {colorSpaceConversion: 'none'});
}

async function run(action) {
    try {
        status('working…');
        await action();
        await rebuild();
    } catch (e) {
        status(String(e.message || e), true);
    }
}

function bindUi() {
    $('mesh').value = state.mesh;
    $('heightmap').onchange = e => run(() => loadHeights(e.target.files[0]));
    $('map').onchange = e => run(() => loadMap(e.target.files[0]));
    $('color').onchange = e => run(() => loadColor(e.target.files[0]));
    $('mesh').onchange = e => run(async () => { state.mesh = e.target.value; });
    $('technique').onchange = e => run(async () => { state.technique = e.target.value; });
    $('max-steps').onchange = e => { state.maxSteps = Number(e.target.value); draw(); };
    $('tiles').value = state.tiles;
    $('tiles').onchange = e => { state.tiles = Number(e.target.value); draw(); };
    $('shadows').checked = state.shadows;
    $('shadows').onchange = e => { state.shadows = e.target.checked; draw(); };
    $('depth-ratio').value = state.depthRatio;
    $('depth-ratio').onchange = e => run(async () => { state.depthRatio = Number(e.target.value); state.depth = null; });
    // Orbit: drag turns (azimuth, elevation), the wheel moves in and out.
    let drag = null;
    canvas.onpointerdown = e => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); };
    canvas.onpointerup = () => { drag = null; };
    canvas.onpointermove = e => {
        if (!drag) return;
        state.view.azimuth -= 0.4 * (e.clientX - drag[0]);
        state.view.elevation = Math.min(89.9, Math.max(-89.9, state.view.elevation + 0.4 * (e.clientY - drag[1])));
        drag = [e.clientX, e.clientY];
        draw();
    };
    canvas.onwheel = e => {
        e.preventDefault();
        state.view.distance = Math.min(20, Math.max(0.6, state.view.distance * Math.exp(0.001 * e.deltaY)));
        draw();
    };
}

if (!gl) {
    status('this browser has no WebGL2', true);
} else {
    if (query.get('ui') === '0') $('panel').hidden = true;
    bindUi();
    run(async () => {
        if (query.has('height')) await loadHeights(query.get('height'));
        if (query.has('map')) await loadMap(query.get('map'));
        if (query.has('color')) await loadColor(query.get('color'));
        if (query.has('technique')) state.technique = query.get('technique');
    });
}
