// HW4 ray tracer in JavaScript (node).
// usage: node tracer.js scene.txt out.ppm
// One ray per pixel through the pixel centre, Phong-style local light
// (ambient + diffuse) with one shadow ray per light, recursive reflection.
'use strict';
const fs = require('fs');
const path = require('path');

const KA = 0.1;          // ambient constant
const MAX_DEPTH = 5;     // reflection bounces
const EPS = 1e-4;        // offset for secondary rays

// ---------- small vector helpers ----------
const v3 = (x, y, z) => ({ x, y, z });
const add = (a, b) => v3(a.x + b.x, a.y + b.y, a.z + b.z);
const sub = (a, b) => v3(a.x - b.x, a.y - b.y, a.z - b.z);
const scale = (a, s) => v3(a.x * s, a.y * s, a.z * s);
const mulv = (a, b) => v3(a.x * b.x, a.y * b.y, a.z * b.z);
const dot = (a, b) => a.x * b.x + a.y * b.y + a.z * b.z;
const cross = (a, b) => v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
const len = (a) => Math.sqrt(dot(a, a));
const norm = (a) => scale(a, 1 / len(a));
const BLACK = v3(0, 0, 0);

// ---------- textures (PPM, P3 or P6) ----------
function readPPM(file) {
  const buf = fs.readFileSync(file);
  let pos = 0;
  function token() {
    for (;;) {
      while (pos < buf.length && /\s/.test(String.fromCharCode(buf[pos]))) pos++;
      if (buf[pos] === 35) { // '#': comment to end of line
        while (pos < buf.length && buf[pos] !== 10) pos++;
      } else break;
    }
    let s = '';
    while (pos < buf.length && !/\s/.test(String.fromCharCode(buf[pos]))) s += String.fromCharCode(buf[pos++]);
    return s;
  }
  const magic = token();
  const w = parseInt(token(), 10), h = parseInt(token(), 10), max = parseInt(token(), 10);
  const px = new Float64Array(w * h * 3);
  if (magic === 'P6') {
    pos++; // single whitespace after maxval
    const bytes = max > 255 ? 2 : 1;
    for (let i = 0; i < w * h * 3; i++) {
      const val = bytes === 2 ? buf[pos] * 256 + buf[pos + 1] : buf[pos];
      pos += bytes;
      px[i] = val / max;
    }
  } else if (magic === 'P3') {
    for (let i = 0; i < w * h * 3; i++) px[i] = parseInt(token(), 10) / max;
  } else {
    throw new Error('unsupported texture ' + file);
  }
  return { w, h, px };
}

function texel(tex, u, v) {
  // u to the right, v up; row 0 of the image is the top
  let x = Math.floor(u * tex.w), y = Math.floor((1 - v) * tex.h);
  x = Math.min(Math.max(x, 0), tex.w - 1);
  y = Math.min(Math.max(y, 0), tex.h - 1);
  const k = (y * tex.w + x) * 3;
  return v3(tex.px[k], tex.px[k + 1], tex.px[k + 2]);
}

// ---------- scene file ----------
function parseScene(file) {
  const dir = path.dirname(file);
  const scene = { size: 0, objects: [], lights: [] };
  let cur = null;
  const nums = (parts) => parts.slice(1).map(Number);
  for (const raw of fs.readFileSync(file, 'utf8').split(/\r?\n/)) {
    const parts = raw.trim().split(/\s+/);
    if (parts[0] === '') continue;
    const key = parts[0].toLowerCase();
    if (key === 'camera') {
      scene.size = parseInt(parts[1], 10);
      cur = null;
    } else if (key === 'sphere' || key === 'plane') {
      cur = { type: key, color: v3(1, 1, 1), refl: 0, tex: null, center: v3(0, 0, 0) };
      scene.objects.push(cur);
    } else if (key === 'light') {
      cur = { type: 'light', pos: v3(0, 0, 0), color: v3(1, 1, 1) };
      scene.lights.push(cur);
    } else if (cur) {
      const n = nums(parts);
      switch (key) {
        case 'dimension': cur.dim = n; break;
        case 'center': cur.center = v3(n[0], n[1], n[2]); break;
        case 'location': cur.pos = v3(n[0], n[1], n[2]); break;
        case 'color': cur.color = v3(n[0], n[1], n[2]); break;
        case 'reflectivity': cur.refl = n[0]; break;
        case 'normal': cur.normal = norm(v3(n[0], n[1], n[2])); break;
        case 'headup': cur.headup = v3(n[0], n[1], n[2]); break;
        case 'texture': cur.tex = readPPM(path.join(dir, parts[1])); break;
        default: break;
      }
    }
  }
  for (const o of scene.objects) {
    if (o.type === 'sphere') {
      o.r = o.dim[0];
    } else {
      // plane: local axes from headup projected onto the plane
      o.w = o.dim[0];
      o.h = o.dim.length > 1 ? o.dim[1] : o.dim[0];
      const up = sub(o.headup, scale(o.normal, dot(o.headup, o.normal)));
      o.up = norm(up);
      o.right = cross(o.up, o.normal);
    }
  }
  return scene;
}

// ---------- intersections ----------
function hitSphere(o, e, d, tmin) {
  // (d.d) t^2 + 2 d.(e-c) t + (e-c).(e-c) - R^2 = 0
  const ec = sub(e, o.center);
  const a = dot(d, d), b = 2 * dot(d, ec), c = dot(ec, ec) - o.r * o.r;
  const disc = b * b - 4 * a * c;
  if (disc < 0) return Infinity;
  const sq = Math.sqrt(disc);
  const t1 = (-b - sq) / (2 * a), t2 = (-b + sq) / (2 * a);
  if (t1 > tmin) return t1;
  if (t2 > tmin) return t2;
  return Infinity;
}

function hitPlane(o, e, d, tmin) {
  const denom = dot(o.normal, d);
  if (Math.abs(denom) < 1e-12) return Infinity;
  const t = dot(o.normal, sub(o.center, e)) / denom;
  if (t <= tmin) return Infinity;
  const local = sub(add(e, scale(d, t)), o.center);
  if (Math.abs(dot(local, o.right)) > o.w / 2 || Math.abs(dot(local, o.up)) > o.h / 2) return Infinity;
  return t;
}

function intersect(o, e, d, tmin) {
  return o.type === 'sphere' ? hitSphere(o, e, d, tmin) : hitPlane(o, e, d, tmin);
}

function closest(scene, e, d, tmin) {
  let best = Infinity, obj = null;
  for (const o of scene.objects) {
    const t = intersect(o, e, d, tmin);
    if (t < best) { best = t; obj = o; }
  }
  return { t: best, obj };
}

function baseColor(o, p) {
  if (!o.tex) return o.color;
  if (o.type === 'sphere') {
    const q = norm(sub(p, o.center));
    const u = 0.5 + Math.atan2(q.x, -q.z) / (2 * Math.PI);
    const v = 0.5 + Math.asin(Math.max(-1, Math.min(1, q.y))) / Math.PI;
    return texel(o.tex, u, v);
  }
  const local = sub(p, o.center);
  return texel(o.tex, dot(local, o.right) / o.w + 0.5, dot(local, o.up) / o.h + 0.5);
}

// ---------- shading ----------
function inShadow(scene, p, n, light) {
  const start = add(p, scale(n, EPS));
  const toL = sub(light.pos, start);
  const dist = len(toL);
  const dir = scale(toL, 1 / dist);
  for (const o of scene.objects) {
    const t = intersect(o, start, dir, 0);
    if (t < dist) return true;
  }
  return false;
}

function trace(scene, e, d, depth) {
  const hit = closest(scene, e, d, 1e-9);
  if (!hit.obj) return BLACK;
  const o = hit.obj;
  const p = add(e, scale(d, hit.t));
  let n = o.type === 'sphere' ? norm(sub(p, o.center)) : o.normal;
  if (dot(n, d) > 0) n = scale(n, -1); // face the viewer
  const base = baseColor(o, p);
  let color = scale(base, KA);
  for (const light of scene.lights) {
    const L = norm(sub(light.pos, p));
    const ndl = dot(n, L);
    if (ndl <= 0) continue;
    if (inShadow(scene, p, n, light)) continue;
    color = add(color, scale(mulv(base, light.color), ndl));
  }
  if (o.refl > 0 && depth < MAX_DEPTH) {
    const v = scale(d, -1);
    const r = norm(sub(scale(n, 2 * dot(n, v)), v)); // r = 2(n.v)n - v
    const start = add(p, scale(n, EPS));
    color = add(color, scale(trace(scene, start, r, depth + 1), o.refl));
  }
  return color;
}

// ---------- main ----------
function main() {
  const [sceneFile, outFile] = process.argv.slice(2);
  if (!sceneFile || !outFile) {
    console.error('usage: node tracer.js scene.txt out.ppm');
    process.exit(1);
  }
  const scene = parseScene(sceneFile);
  const N = scene.size;
  const img = Buffer.alloc(N * N * 3);
  const eye = v3(0, 0, 0);
  const to8 = (c) => Math.round(Math.min(1, Math.max(0, c)) * 255);
  for (let j = 0; j < N; j++) {
    for (let i = 0; i < N; i++) {
      // pixel centre on the 1x1 image plane at z = -1
      const s = v3(-0.5 + (i + 0.5) / N, 0.5 - (j + 0.5) / N, -1);
      const c = trace(scene, eye, norm(sub(s, eye)), 0);
      const k = (j * N + i) * 3;
      img[k] = to8(c.x);
      img[k + 1] = to8(c.y);
      img[k + 2] = to8(c.z);
    }
  }
  fs.writeFileSync(outFile, Buffer.concat([Buffer.from(`P6\n${N} ${N}\n255\n`), img]));
}

main();
