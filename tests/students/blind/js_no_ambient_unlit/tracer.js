#!/usr/bin/env node
// HW4 ray tracer in plain JavaScript (node, standard library only).
// Usage: node tracer.js scene_description_file output_image
'use strict';

const fs = require('fs');
const path = require('path');

const AMBIENT = 0.1;   // k_a
const MAX_DEPTH = 6;   // how many reflection bounces we follow
const EPSILON = 1e-4;  // secondary rays start this far along their direction

function die(msg) {
  process.stderr.write('tracer: ' + msg + '\n');
  process.exit(1);
}

// ---------- small vector helpers (arrays [x, y, z]) ----------
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const mul = (a, b) => [a[0] * b[0], a[1] * b[1], a[2] * b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = (a) => Math.sqrt(dot(a, a));
function normalize(a) {
  const l = length(a);
  return l > 0 ? scale(a, 1 / l) : a;
}

// ---------- PPM texture loading (P3 / P6, comments allowed) ----------
function loadPPM(file) {
  let buf;
  try {
    buf = fs.readFileSync(file);
  } catch (e) {
    throw new Error('cannot read texture ' + file + ' (' + e.code + ')');
  }
  let pos = 0;
  const isSpace = (c) => c === 32 || c === 9 || c === 10 || c === 13 || c === 11 || c === 12;
  function nextToken() {
    for (;;) {
      while (pos < buf.length && isSpace(buf[pos])) pos++;
      if (pos < buf.length && buf[pos] === 35) { // '#'
        while (pos < buf.length && buf[pos] !== 10 && buf[pos] !== 13) pos++;
        continue;
      }
      break;
    }
    const start = pos;
    while (pos < buf.length && !isSpace(buf[pos]) && buf[pos] !== 35) pos++;
    if (start === pos) throw new Error('texture ' + file + ' is truncated');
    return buf.toString('latin1', start, pos);
  }
  const magic = nextToken();
  if (magic !== 'P3' && magic !== 'P6') throw new Error('texture ' + file + ' is not a P3/P6 PPM');
  const width = parseInt(nextToken(), 10);
  const height = parseInt(nextToken(), 10);
  const maxval = parseInt(nextToken(), 10);
  if (!(width > 0 && height > 0 && maxval > 0 && maxval < 65536)) {
    throw new Error('texture ' + file + ' has a bad header');
  }
  const count = width * height * 3;
  const pixels = new Float64Array(count);
  if (magic === 'P3') {
    for (let i = 0; i < count; i++) {
      const v = Number(nextToken());
      if (Number.isNaN(v)) throw new Error('texture ' + file + ' has a bad sample');
      pixels[i] = v / maxval;
    }
  } else {
    pos += 1; // exactly one whitespace byte after maxval
    const wide = maxval > 255;
    if (buf.length < pos + count * (wide ? 2 : 1)) throw new Error('texture ' + file + ' is truncated');
    for (let i = 0; i < count; i++) {
      const v = wide ? (buf[pos + 2 * i] << 8) | buf[pos + 2 * i + 1] : buf[pos + i];
      pixels[i] = v / maxval;
    }
  }
  return { width, height, pixels };
}

// u, v in [0, 1], v = 0 at the top row of the texture image
function texel(tex, u, v) {
  u -= Math.floor(u);
  v -= Math.floor(v);
  const x = Math.min(tex.width - 1, Math.floor(u * tex.width));
  const y = Math.min(tex.height - 1, Math.floor(v * tex.height));
  const i = (y * tex.width + x) * 3;
  return [tex.pixels[i], tex.pixels[i + 1], tex.pixels[i + 2]];
}

// ---------- scene parsing ----------
function parseScene(file) {
  let text;
  try {
    text = fs.readFileSync(file, 'utf8');
  } catch (e) {
    die('cannot read scene file ' + file + ' (' + e.code + ')');
  }
  const scene = { resolution: 0, objects: [], lights: [] };
  let hasCamera = false;
  let current = null;

  const lines = text.split(/\r\n|\r|\n/);
  lines.forEach((rawLine, idx) => {
    const hash = rawLine.indexOf('#');
    const line = (hash >= 0 ? rawLine.slice(0, hash) : rawLine).trim();
    if (line === '') return;
    const parts = line.split(/\s+/);
    const key = parts[0].toLowerCase();
    const rest = parts.slice(1);
    const nums = (n) => {
      if (rest.length < n) die('line ' + (idx + 1) + ': "' + key + '" needs ' + n + ' value(s)');
      const out = rest.slice(0, n).map(Number);
      if (out.some((x) => !Number.isFinite(x))) die('line ' + (idx + 1) + ': bad number in "' + line + '"');
      return out;
    };

    switch (key) {
      case 'camera': {
        const r = Math.floor(nums(1)[0]);
        if (r < 1) die('camera resolution must be at least 1');
        scene.resolution = r;
        hasCamera = true;
        current = null;
        return;
      }
      case 'sphere':
      case 'plane':
        current = {
          type: key, size: key === 'sphere' ? [1] : [1, 1], center: [0, 0, 0], color: [1, 1, 1],
          reflectivity: 0, textureFile: null, texture: null, normal: [0, 0, 1], headup: [0, 1, 0],
        };
        scene.objects.push(current);
        return;
      case 'light':
        current = { type: 'light', location: [0, 0, 0], color: [1, 1, 1] };
        scene.lights.push(current);
        return;
      default:
        break;
    }
    if (current === null) {
      process.stderr.write('tracer: warning: line ' + (idx + 1) + ' ignored: ' + line + '\n');
      return;
    }
    if (current.type === 'light') {
      if (key === 'location' || key === 'position') current.location = nums(3);
      else if (key === 'color' || key === 'colour') current.color = nums(3);
      else process.stderr.write('tracer: warning: unknown light attribute ' + key + '\n');
      return;
    }
    switch (key) {
      case 'dimension': current.size = nums(current.type === 'sphere' ? 1 : 2); break;
      case 'center': current.center = nums(3); break;
      case 'color': case 'colour': current.color = nums(3); break;
      case 'reflectivity': current.reflectivity = nums(1)[0]; break;
      case 'normal': current.normal = nums(3); break;
      case 'headup': current.headup = nums(3); break;
      case 'texture':
        if (rest.length === 0) die('line ' + (idx + 1) + ': texture needs a file name');
        current.textureFile = rest.join(' ');
        break;
      default:
        process.stderr.write('tracer: warning: unknown attribute ' + key + '\n');
    }
  });

  if (!hasCamera) die('scene file has no camera');

  const dir = path.dirname(file);
  for (const obj of scene.objects) {
    if (obj.textureFile !== null) {
      try {
        obj.texture = loadPPM(path.resolve(dir, obj.textureFile));
      } catch (e) {
        die(e.message);
      }
    }
    if (obj.type === 'plane') {
      const n = normalize(obj.normal);
      let up = sub(obj.headup, scale(n, dot(obj.headup, n)));
      if (length(up) < 1e-9) {
        const helper = Math.abs(n[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
        up = sub(helper, scale(n, dot(helper, n)));
      }
      obj.n = n;
      obj.up = normalize(up);
      obj.right = normalize(cross(obj.up, n));
    }
  }
  return scene;
}

// ---------- intersection ----------
// returns the smallest t > tMin or Infinity
function hitSphere(s, o, d, tMin) {
  const R = s.size[0];
  const ec = sub(o, s.center);
  const a = dot(d, d);
  const b = 2 * dot(d, ec);
  const c = dot(ec, ec) - R * R;
  const disc = b * b - 4 * a * c;
  if (disc < 0) return Infinity;
  const root = Math.sqrt(disc);
  const tMinus = (-b - root) / (2 * a);
  if (tMinus > tMin) return tMinus;
  const tPlus = (-b + root) / (2 * a);
  if (tPlus > tMin) return tPlus;
  return Infinity;
}

function hitPlane(p, o, d, tMin) {
  const denom = dot(p.n, d);
  if (Math.abs(denom) < 1e-12) return Infinity;
  const t = dot(p.n, sub(p.center, o)) / denom;
  if (t <= tMin) return Infinity;
  const local = sub(add(o, scale(d, t)), p.center);
  if (Math.abs(dot(local, p.right)) > p.size[0] / 2) return Infinity;
  if (Math.abs(dot(local, p.up)) > p.size[1] / 2) return Infinity;
  return t;
}

function hitObject(obj, o, d, tMin) {
  return obj.type === 'sphere' ? hitSphere(obj, o, d, tMin) : hitPlane(obj, o, d, tMin);
}

function nearest(scene, o, d) {
  let best = Infinity;
  let bestObj = null;
  for (const obj of scene.objects) {
    const t = hitObject(obj, o, d, 0);
    if (t < best) {
      best = t;
      bestObj = obj;
    }
  }
  return bestObj ? { t: best, obj: bestObj } : null;
}

function blocked(scene, o, d, maxT) {
  for (const obj of scene.objects) {
    if (hitObject(obj, o, d, 0) < maxT) return true;
  }
  return false;
}

// ---------- shading ----------
function objectColor(obj, point, outward) {
  if (!obj.texture) return obj.color;
  if (obj.type === 'sphere') {
    const u = 0.5 + Math.atan2(outward[0], outward[2]) / (2 * Math.PI);
    const v = 0.5 - Math.asin(Math.max(-1, Math.min(1, outward[1]))) / Math.PI;
    return texel(obj.texture, u, v);
  }
  const local = sub(point, obj.center);
  let u = dot(local, obj.right) / obj.size[0] + 0.5;
  let v = 0.5 - dot(local, obj.up) / obj.size[1];
  u = Math.min(Math.max(u, 0), 0.999999);
  v = Math.min(Math.max(v, 0), 0.999999);
  return texel(obj.texture, u, v);
}

function trace(scene, origin, dir, depth) {
  const hit = nearest(scene, origin, dir);
  if (!hit) return [0, 0, 0];
  const obj = hit.obj;
  const point = add(origin, scale(dir, hit.t));
  const outward = obj.type === 'sphere' ? normalize(sub(point, obj.center)) : obj.n;
  const normal = dot(outward, dir) > 0 ? scale(outward, -1) : outward;
  const base = objectColor(obj, point, outward);

  let color = [0, 0, 0];
  let lit = false;

  // diffuse from each light that is visible
  for (const light of scene.lights) {
    const toLight = sub(light.location, point);
    const dist = length(toLight);
    const L = scale(toLight, 1 / dist);
    const cosine = dot(normal, L);
    if (cosine <= 0) continue;
    const start = add(point, scale(L, EPSILON));
    if (blocked(scene, start, L, dist - EPSILON)) continue;
    color = add(color, scale(mul(base, light.color), cosine));
    lit = true;
  }
  if (lit) color = add(color, scale(base, AMBIENT)); // ambient only where some light arrives

  // mirror reflection
  if (obj.reflectivity > 0 && depth < MAX_DEPTH) {
    const v = normalize(scale(dir, -1));
    const r = normalize(sub(scale(normal, 2 * dot(normal, v)), v));
    const start = add(point, scale(r, EPSILON));
    const reflected = trace(scene, start, r, depth + 1);
    color = add(color, scale(reflected, obj.reflectivity));
  }
  return color;
}

function toByte(x) {
  if (!(x > 0)) return 0;
  if (x >= 1) return 255;
  return Math.round(x * 255);
}

function main() {
  const args = process.argv.slice(2);
  if (args.length !== 2) die('usage: node tracer.js scene_description_file output_image');
  const scene = parseScene(args[0]);
  const N = scene.resolution;
  const out = [];
  out.push('P3');
  out.push(N + ' ' + N);
  out.push('255');
  for (let row = 0; row < N; row++) {
    for (let col = 0; col < N; col++) {
      // centre of the pixel on the image plane z = -1, which spans [-0.5, 0.5]^2
      const x = (col + 0.5) / N - 0.5;
      const y = 0.5 - (row + 0.5) / N;
      const c = trace(scene, [0, 0, 0], normalize([x, y, -1]), 0);
      out.push(toByte(c[0]) + ' ' + toByte(c[1]) + ' ' + toByte(c[2]));
    }
  }
  try {
    fs.writeFileSync(args[1], out.join('\n') + '\n');
  } catch (e) {
    die('cannot write ' + args[1] + ' (' + e.code + ')');
  }
}

main();
