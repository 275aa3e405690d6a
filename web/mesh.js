// The built-in meshes and the orbit camera of the web preview, as src/relief/preview/mesh.cpp and
// src/relief/render/camera.cpp make them (same vertices, uv, tangent frames, normalization, and
// the same eye, so a page view and `relief render --mesh` of the same options agree): z up, the
// mesh centred and scaled to a bounding radius of 1, v growing downwards on a face seen upright.
// A vertex is 14 floats: position 3, normal 3, uv 2, tangent 4 (w: handedness), uvScale 2.

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = a => Math.sqrt(dot(a, a));
const normalize = a => scale(a, 1 / length(a));

function addQuad(mesh, corner, a, b) {
    const first = mesh.vertices.length;
    const n = normalize(cross(a, b));
    for (let k = 0; k < 4; ++k) {
        const s = k & 1, t = k >> 1;
        mesh.vertices.push({p: add(corner, add(scale(a, s), scale(b, t))), n, uv: [s, t]});
    }
    for (const i of [0, 1, 3, 0, 3, 2]) mesh.indices.push(first + i);
}

function addGrid(mesh, columns, rows, at) {
    const first = mesh.vertices.length;
    for (let j = 0; j <= rows; ++j)
        for (let i = 0; i <= columns; ++i) {
            const uv = [i / columns, j / rows];
            const [p, n] = at(uv[0], uv[1]);
            mesh.vertices.push({p, n, uv});
        }
    const stride = columns + 1;
    for (let j = 0; j < rows; ++j)
        for (let i = 0; i < columns; ++i) {
            const a = first + j * stride + i, b = a + 1, c = a + stride, d = c + 1;
            mesh.indices.push(a, d, b, a, c, d);
        }
}

function swapWinding(mesh, from) {
    for (let k = from; k < mesh.indices.length; k += 3)
        [mesh.indices[k + 1], mesh.indices[k + 2]] = [mesh.indices[k + 2], mesh.indices[k + 1]];
}

function plane() {
    const m = {vertices: [], indices: []};
    addQuad(m, [-1, 1, 0], [2, 0, 0], [0, -2, 0]);
    for (const v of m.vertices) v.n = [0, 0, 1];
    swapWinding(m, 0);
    return m;
}

function cube() {
    const m = {vertices: [], indices: []};
    const faces = [
        [[-1, -1, 1], [2, 0, 0], [0, 0, -2]], [[1, -1, 1], [0, 2, 0], [0, 0, -2]],
        [[1, 1, 1], [-2, 0, 0], [0, 0, -2]], [[-1, 1, 1], [0, -2, 0], [0, 0, -2]],
        [[-1, 1, 1], [2, 0, 0], [0, -2, 0]], [[-1, -1, -1], [2, 0, 0], [0, 2, 0]],
    ];
    for (const [corner, a, b] of faces) {
        addQuad(m, corner, a, b);
        swapWinding(m, m.indices.length - 6);
        for (const v of m.vertices.slice(-4)) v.n = scale(v.n, -1);
    }
    return m;
}

function sphere() {
    const m = {vertices: [], indices: []};
    addGrid(m, 64, 32, (s, t) => {
        const phi = 2 * Math.PI * s, theta = Math.PI * t;
        const n = [Math.sin(theta) * Math.cos(phi), Math.sin(theta) * Math.sin(phi), Math.cos(theta)];
        return [n, n];
    });
    return m;
}

function cylinder() {
    const m = {vertices: [], indices: []};
    addGrid(m, 64, 1, (s, t) => {
        const phi = 2 * Math.PI * s, n = [Math.cos(phi), Math.sin(phi), 0];
        return [add(n, [0, 0, 1 - 2 * t]), n];
    });
    for (const z of [1, -1]) {
        const first = m.vertices.length;
        addGrid(m, 32, 1, (s, t) => {
            const phi = 2 * Math.PI * s, r = 1 - t;
            return [[r * Math.cos(phi), r * Math.sin(phi), z], [0, 0, z]];
        });
        for (const v of m.vertices.slice(first)) v.uv = [0.5 + 0.5 * v.p[0], 0.5 - 0.5 * z * v.p[1]];
        if (z > 0) swapWinding(m, m.indices.length - 6 * 32);
    }
    return m;
}

// computeTangentFrames (mesh.cpp): area-weighted dP/du, dP/dv and their lengths per vertex.
function tangentFrames(mesh) {
    const n = mesh.vertices.length;
    const du = Array.from({length: n}, () => [0, 0, 0]), dv = Array.from({length: n}, () => [0, 0, 0]);
    const sc = Array.from({length: n}, () => [0, 0]), weight = new Array(n).fill(0);
    for (let k = 0; k + 2 < mesh.indices.length; k += 3) {
        const i = mesh.indices.slice(k, k + 3);
        const [a, b, c] = i.map(j => mesh.vertices[j]);
        const e1 = sub(b.p, a.p), e2 = sub(c.p, a.p);
        const t1 = [b.uv[0] - a.uv[0], b.uv[1] - a.uv[1]], t2 = [c.uv[0] - a.uv[0], c.uv[1] - a.uv[1]];
        const det = t1[0] * t2[1] - t2[0] * t1[1];
        const area = 0.5 * length(cross(e1, e2));
        if (Math.abs(det) < 1e-12 || area <= 0) continue;
        const dPdu = scale(sub(scale(e1, t2[1]), scale(e2, t1[1])), 1 / det);
        const dPdv = scale(sub(scale(e2, t1[0]), scale(e1, t2[0])), 1 / det);
        for (const v of i) {
            du[v] = add(du[v], scale(dPdu, area));
            dv[v] = add(dv[v], scale(dPdv, area));
            sc[v] = [sc[v][0] + area * length(dPdu), sc[v][1] + area * length(dPdv)];
            weight[v] += area;
        }
    }
    mesh.vertices.forEach((m, v) => {
        m.uvScale = weight[v] > 0 ? [sc[v][0] / weight[v], sc[v][1] / weight[v]] : [1, 1];
        m.uvScale = m.uvScale.map(x => Math.max(x, 1e-6));
        let t = sub(du[v], scale(m.n, dot(m.n, du[v])));
        if (dot(t, t) < 1e-20) t = cross(m.n, Math.abs(m.n[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0]);
        t = normalize(t);
        m.tangent = [...t, dot(cross(m.n, t), dv[v]) < 0 ? -1 : 1];
    });
}

function normalizeMesh(mesh) {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const v of mesh.vertices)
        for (let c = 0; c < 3; ++c) lo[c] = Math.min(lo[c], v.p[c]), hi[c] = Math.max(hi[c], v.p[c]);
    const centre = scale(add(lo, hi), 0.5);
    const radius = Math.max(...mesh.vertices.map(v => length(sub(v.p, centre))));
    const s = radius > 0 ? 1 / radius : 1;
    for (const v of mesh.vertices) {
        v.p = scale(sub(v.p, centre), s);
        v.uvScale = v.uvScale.map(x => x * s);
    }
}

export const kMeshes = {plane, cube, sphere, cylinder};

// {vertices: Float32Array (14 floats each), indices: Uint32Array}
export function builtinMesh(name) {
    if (!(name in kMeshes)) throw new Error(`mesh '${name}': expected ${Object.keys(kMeshes).join(', ')}`);
    const mesh = kMeshes[name]();
    tangentFrames(mesh);
    normalizeMesh(mesh);
    const out = new Float32Array(mesh.vertices.length * 14);
    mesh.vertices.forEach((v, k) => out.set([...v.p, ...v.n, ...v.uv, ...v.tangent, ...v.uvScale], 14 * k));
    return {vertices: out, indices: Uint32Array.from(mesh.indices)};
}

export function directionFromAngles(elevationDeg, azimuthDeg) {
    const el = elevationDeg * Math.PI / 180, az = azimuthDeg * Math.PI / 180;
    return [Math.cos(el) * Math.cos(az), Math.cos(el) * Math.sin(az), Math.sin(el)];
}

// Camera(OrbitView, target 0, diameter 2, w, h) and clipFromWorld (mesh_renderer.cpp): the eye,
// and the column-major perspective × look-at matrix with near/far around a scene of radius 1.8.
export function orbitCamera(view, width, height) {
    const eye = scale(directionFromAngles(view.elevation, view.azimuth), view.distance * 2);
    const forward = normalize(scale(eye, -1));
    const worldUp = Math.abs(forward[2]) > 0.9999 ? scale(directionFromAngles(0, view.azimuth), -1) : [0, 0, 1];
    const right = normalize(cross(forward, worldUp));
    const up = cross(right, forward);
    const d = length(eye), near = Math.max(0.01 * d, d - 1.8), far = d + 1.8;
    const f = 1 / Math.tan(0.5 * view.fov * Math.PI / 180), aspect = width / height;
    const proj = [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / (near - far), -1,
                  0, 0, 2 * far * near / (near - far), 0];
    const viewM = [right[0], up[0], -forward[0], 0, right[1], up[1], -forward[1], 0,
                   right[2], up[2], -forward[2], 0,
                   -dot(right, eye), -dot(up, eye), dot(forward, eye), 1];
    const clip = new Float32Array(16);
    for (let c = 0; c < 4; ++c)
        for (let r = 0; r < 4; ++r) {
            let s = 0;
            for (let k = 0; k < 4; ++k) s += proj[k * 4 + r] * viewM[c * 4 + k];
            clip[c * 4 + r] = s;
        }
    return {eye, clip};
}
