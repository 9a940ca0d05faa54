#!/usr/bin/env node
// HW4 ray tracer - JavaScript (node) version
// usage: node tracer.js scene_description_file output_image
'use strict';
const fs = require('fs');
const path = require('path');

// ---------------- vectors (plain arrays) ----------------
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const mul = (a, b) => [a[0] * b[0], a[1] * b[1], a[2] * b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = (a) => Math.sqrt(dot(a, a));
const normalize = (a) => { const l = length(a); return l > 0 ? scale(a, 1 / l) : a; };

class SceneError extends Error {}
function fail(msg) { throw new SceneError(msg); }

// ---------------- PPM reader (P3 / P6) ----------------
function readPPM(file) {
  let buf;
  try { buf = fs.readFileSync(file); } catch (e) { fail(`cannot read texture ${file}: ${e.code || e.message}`); }
  let i = 0;
  const isSpace = (c) => c === 32 || c === 9 || c === 10 || c === 13 || c === 11 || c === 12;
  function token() {
    for (;;) {
      while (i < buf.length && isSpace(buf[i])) i++;
      if (i < buf.length && buf[i] === 35) { // '#' comment
        while (i < buf.length && buf[i] !== 10 && buf[i] !== 13) i++;
        continue;
      }
      break;
    }
    const s = i;
    while (i < buf.length && !isSpace(buf[i]) && buf[i] !== 35) i++;
    if (s === i) fail(`texture ${file}: unexpected end of file`);
    return buf.toString('latin1', s, i);
  }
  const magic = token();
  if (magic !== 'P3' && magic !== 'P6') fail(`texture ${file}: not a P3/P6 ppm`);
  const w = parseInt(token(), 10), h = parseInt(token(), 10), maxval = parseInt(token(), 10);
  if (!(w > 0) || !(h > 0) || !(maxval > 0) || maxval > 65535) fail(`texture ${file}: bad header`);
  const data = new Float32Array(w * h * 3);
  if (magic === 'P3') {
    for (let k = 0; k < w * h * 3; k++) {
      const v = parseInt(token(), 10);
      if (isNaN(v)) fail(`texture ${file}: bad sample`);
      data[k] = v / maxval;
    }
  } else {
    i++; // single whitespace after maxval
    const two = maxval > 255;
    if (buf.length - i < w * h * 3 * (two ? 2 : 1)) fail(`texture ${file}: truncated data`);
    for (let k = 0; k < w * h * 3; k++) {
      let v;
      if (two) { v = buf[i] * 256 + buf[i + 1]; i += 2; } else { v = buf[i]; i++; }
      data[k] = v / maxval;
    }
  }
  return { w, h, data };
}

function texel(tex, u, v) {
  u -= Math.floor(u);
  v = Math.min(1, Math.max(0, v));
  let x = Math.floor(u * tex.w), y = Math.floor(v * tex.h);
  if (x >= tex.w) x = tex.w - 1;
  if (y >= tex.h) y = tex.h - 1;
  const k = (y * tex.w + x) * 3;
  return [tex.data[k], tex.data[k + 1], tex.data[k + 2]];
}

// ---------------- scene parser ----------------
function parseScene(file) {
  let text;
  try { text = fs.readFileSync(file, 'utf8'); } catch (e) { fail(`cannot read scene file ${file}: ${e.code || e.message}`); }
  const dir = path.dirname(file);
  const scene = { res: 0, objects: [], lights: [] };
  let cur = null; // current object or light
  let sawCamera = false;
  const lines = text.split('\n');
  const nums = (words, n, ln) => {
    if (words.length !== n + 1) fail(`line ${ln}: '${words[0]}' needs ${n} value(s)`);
    return words.slice(1).map((w) => {
      const v = Number(w);
      if (w === '' || !isFinite(v)) fail(`line ${ln}: '${w}' is not a number`);
      return v;
    });
  };
  for (let idx = 0; idx < lines.length; idx++) {
    const ln = idx + 1;
    const line = lines[idx].replace(/\r$/, '').trim();
    if (line === '' || line.startsWith('#')) continue;
    const words = line.split(/\s+/);
    const key = words[0].toLowerCase();
    if (key === 'camera') {
      if (sawCamera) fail(`line ${ln}: only one camera allowed`);
      const [n] = nums(words, 1, ln);
      if (!Number.isInteger(n) || n <= 0) fail(`line ${ln}: camera resolution must be a positive integer`);
      scene.res = n; sawCamera = true; cur = null;
    } else if (key === 'sphere' || key === 'plane') {
      if (words.length !== 1) fail(`line ${ln}: unexpected values after ${key}`);
      cur = { kind: key, color: [1, 1, 1], reflectivity: 0, tex: null, set: {} };
      scene.objects.push(cur);
    } else if (key === 'light') {
      if (words.length !== 1) fail(`line ${ln}: unexpected values after light`);
      cur = { kind: 'light', color: [1, 1, 1], set: {} };
      scene.lights.push(cur);
    } else {
      if (!cur) fail(`line ${ln}: '${words[0]}' is not inside a sphere/plane/light section`);
      const allowed = cur.kind === 'light' ? ['location', 'color']
        : cur.kind === 'sphere' ? ['dimension', 'center', 'color', 'reflectivity', 'texture']
          : ['dimension', 'center', 'color', 'reflectivity', 'texture', 'normal', 'headup'];
      if (!allowed.includes(key)) fail(`line ${ln}: unknown keyword '${words[0]}' in ${cur.kind}`);
      switch (key) {
        case 'location': cur.location = nums(words, 3, ln); break;
        case 'color': cur.color = nums(words, 3, ln); break;
        case 'center': cur.center = nums(words, 3, ln); break;
        case 'reflectivity': cur.reflectivity = nums(words, 1, ln)[0]; break;
        case 'normal': cur.normal = nums(words, 3, ln); break;
        case 'headup': cur.headup = nums(words, 3, ln); break;
        case 'dimension':
          cur.dimension = nums(words, cur.kind === 'sphere' ? 1 : 2, ln);
          if (cur.dimension.some((d) => d <= 0)) fail(`line ${ln}: dimension must be positive`);
          break;
        case 'texture': {
          if (words.length < 2) fail(`line ${ln}: texture needs a file name`);
          const name = line.slice(words[0].length).trim();
          cur.tex = readPPM(path.resolve(dir, name));
          break;
        }
      }
      cur.set[key] = true;
    }
  }
  if (!sawCamera) fail('no camera line in scene');
  for (const o of scene.objects) {
    if (!o.set.center || !o.set.dimension) fail(`${o.kind} without center or dimension`);
    if (o.kind === 'sphere') {
      o.radius = o.dimension[0];
    } else {
      if (!o.set.normal) fail('plane without normal');
      o.n = normalize(o.normal);
      if (length(o.normal) === 0) fail('plane normal is zero');
      let up = o.headup || (Math.abs(o.n[1]) < 0.9 ? [0, 1, 0] : [0, 0, -1]);
      up = sub(up, scale(o.n, dot(up, o.n)));
      if (length(up) < 1e-9) up = sub([1, 0, 0], scale(o.n, o.n[0]));
      if (length(up) < 1e-9) up = sub([0, 0, 1], scale(o.n, o.n[2]));
      o.up = normalize(up);
      o.right = normalize(cross(o.n, o.up));
      o.d = -dot(o.n, o.center); // ax + by + cz + d = 0
      o.w = o.dimension[0]; o.h = o.dimension[1];
    }
  }
  for (const l of scene.lights) if (!l.set.location) fail('light without location');
  return scene;
}

// ---------------- tracing ----------------
const EPS = 1e-3;
const MAX_DEPTH = 4;
const KA = 0.1;      // ambient
const KS = 0.5;      // Phong highlight strength
const SHININESS = 32;
const BACKGROUND = [0, 0, 0];

function intersect(o, e, d) {
  if (o.kind === 'sphere') {
    const ec = sub(e, o.center);
    const a = 1; // d is a direction
    const b = 2 * dot(d, ec);
    const c = dot(ec, ec) - o.radius * o.radius;
    const disc = b * b - 4 * a * c;
    if (disc < 0) return Infinity;
    const sq = Math.sqrt(disc);
    const t1 = (-b - sq) / (2 * a);
    if (t1 > EPS) return t1;
    const t2 = (-b + sq) / (2 * a);
    if (t2 > EPS) return t2;
    return Infinity;
  }
  const den = dot(o.n, d);
  if (Math.abs(den) < 1e-12) return Infinity;
  const t = -(dot(o.n, e) + o.d) / den;
  if (!(t > EPS)) return Infinity;
  const q = sub(add(e, scale(d, t)), o.center);
  if (Math.abs(dot(q, o.right)) > o.w / 2 || Math.abs(dot(q, o.up)) > o.h / 2) return Infinity;
  return t;
}

function colorAt(o, p) {
  if (!o.tex) return o.color;
  let u, v;
  if (o.kind === 'sphere') {
    const n = normalize(sub(p, o.center));
    u = 0.5 + Math.atan2(n[0], n[2]) / (2 * Math.PI);
    v = Math.acos(Math.max(-1, Math.min(1, n[1]))) / Math.PI;
  } else {
    const q = sub(p, o.center);
    u = dot(q, o.right) / o.w + 0.5;
    v = 0.5 - dot(q, o.up) / o.h;
  }
  return texel(o.tex, u, v);
}

function firstHit(scene, e, d) {
  let best = null, bestT = Infinity;
  for (const o of scene.objects) {
    const t = intersect(o, e, d);
    if (t < bestT) { bestT = t; best = o; }
  }
  return best ? { obj: best, t: bestT } : null;
}

function blocked(scene, p, L, dist) {
  for (const o of scene.objects) {
    if (intersect(o, p, L) < dist) return true;
  }
  return false;
}

function trace(scene, e, d, depth) {
  const hit = firstHit(scene, e, d);
  if (!hit) return BACKGROUND;
  const o = hit.obj;
  const p = add(e, scale(d, hit.t));
  let n = o.kind === 'sphere' ? normalize(sub(p, o.center)) : o.n;
  const v = normalize(scale(d, -1)); // towards the viewer
  if (dot(n, v) < 0) n = scale(n, -1); // planes are two-sided
  const base = colorAt(o, p);
  let color = scale(base, KA);
  const origin = add(p, scale(n, EPS));
  for (const light of scene.lights) {
    const toL = sub(light.location, p);
    const dist = length(toL);
    const L = scale(toL, 1 / dist);
    const ndotl = dot(n, L);
    if (ndotl <= 0) continue;
    if (blocked(scene, origin, L, dist)) continue;
    color = add(color, scale(mul(base, light.color), ndotl));
    // Phong highlight
    const R = sub(scale(n, 2 * ndotl), L);
    const rv = dot(R, v);
    if (rv > 0) color = add(color, scale(light.color, KS * Math.pow(rv, SHININESS)));
  }
  if (o.reflectivity > 0 && depth < MAX_DEPTH) {
    const r = normalize(sub(scale(n, 2 * dot(n, v)), v));
    const rc = trace(scene, origin, r, depth + 1);
    color = add(color, scale(rc, o.reflectivity));
  }
  return color;
}

function render(scene) {
  const N = scene.res;
  const out = Buffer.alloc(N * N * 3);
  const eye = [0, 0, 0];
  let k = 0;
  for (let row = 0; row < N; row++) {
    for (let col = 0; col < N; col++) {
      // pixel centre on the 1x1 image plane at z = -1; p(t) = t*s
      const s = [-0.5 + (col + 0.5) / N, 0.5 - (row + 0.5) / N, -1];
      const c = trace(scene, eye, s, 0);
      for (let ch = 0; ch < 3; ch++) {
        const x = Math.min(1, Math.max(0, c[ch]));
        out[k++] = Math.floor(x * 255 + 0.5);
      }
    }
  }
  return out;
}

function main() {
  const args = process.argv.slice(2);
  if (args.length !== 2) {
    process.stderr.write('usage: node tracer.js scene_description_file output_image\n');
    process.exit(1);
  }
  let scene;
  try {
    scene = parseScene(args[0]);
  } catch (e) {
    if (e instanceof SceneError) { process.stderr.write(`error: ${e.message}\n`); process.exit(1); }
    throw e;
  }
  const pixels = render(scene);
  const header = Buffer.from(`P6\n${scene.res} ${scene.res}\n255\n`, 'latin1');
  try {
    fs.writeFileSync(args[1], Buffer.concat([header, pixels]));
  } catch (e) {
    process.stderr.write(`error: cannot write ${args[1]}: ${e.message}\n`);
    process.exit(1);
  }
}

main();
