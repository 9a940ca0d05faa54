#!/usr/bin/env python3
"""HW4 ray tracer (Python 3, standard library only).

usage: python3 tracer.py scene_description_file output_image

Reads the scene format of the assignment (camera / sphere / plane / light
sections) and writes an ASCII PPM (P3) of N x N pixels.
"""
import math
import os
import sys

KA = 0.2          # ambient coefficient
MAX_DEPTH = 8     # maximum number of mirror bounces
EPS = 1e-4        # secondary rays start this far off the surface
T_MIN = 1e-7      # smallest accepted ray parameter
BACKGROUND = (0.0, 0.0, 0.0)


class SceneError(Exception):
    pass


# --------------------------------------------------------------- PPM input

def load_ppm(path, shown):
    try:
        with open(path, 'rb') as f:
            data = f.read()
    except OSError as e:
        raise SceneError('cannot open texture %s: %s' % (shown, e.strerror))
    if len(data) < 2 or data[0:1] != b'P' or data[1:2] not in (b'3', b'6'):
        raise SceneError('texture %s is not a P3 or P6 PPM file' % shown)
    binary = data[1:2] == b'6'
    pos = 2
    n = len(data)

    def skip(pos):
        while pos < n:
            c = data[pos]
            if c == 35:  # '#'
                while pos < n and data[pos] not in (10, 13):
                    pos += 1
            elif c in (32, 9, 10, 11, 12, 13):
                pos += 1
            else:
                break
        return pos

    def number(pos, what):
        pos = skip(pos)
        start = pos
        while pos < n and 48 <= data[pos] <= 57:
            pos += 1
        if start == pos:
            raise SceneError('texture %s: bad or missing %s' % (shown, what))
        return int(data[start:pos]), pos

    w, pos = number(pos, 'width')
    h, pos = number(pos, 'height')
    maxval, pos = number(pos, 'maxval')
    if w <= 0 or h <= 0:
        raise SceneError('texture %s: bad size' % shown)
    if maxval <= 0 or maxval > 65535:
        raise SceneError('texture %s: bad maxval %d' % (shown, maxval))
    count = w * h * 3
    if binary:
        if pos >= n or data[pos] not in (32, 9, 10, 11, 12, 13):
            raise SceneError('texture %s: bad header' % shown)
        pos += 1
        if maxval < 256:
            raw = data[pos:pos + count]
            if len(raw) < count:
                raise SceneError('texture %s: pixel data is truncated' % shown)
            vals = list(raw)
        else:
            raw = data[pos:pos + 2 * count]
            if len(raw) < 2 * count:
                raise SceneError('texture %s: pixel data is truncated' % shown)
            vals = [(raw[2 * i] << 8) | raw[2 * i + 1] for i in range(count)]
    else:
        # ASCII: strip comments, then split
        text = data[pos:].decode('latin-1')
        toks = []
        for line in text.splitlines():
            k = line.find('#')
            if k >= 0:
                line = line[:k]
            toks.extend(line.split())
        if len(toks) < count:
            raise SceneError('texture %s: pixel data is truncated' % shown)
        try:
            vals = [int(t) for t in toks[:count]]
        except ValueError:
            raise SceneError('texture %s: bad sample value' % shown)
    if any(v < 0 or v > maxval for v in vals):
        raise SceneError('texture %s: sample out of range' % shown)
    inv = 1.0 / maxval
    pixels = [(vals[i] * inv, vals[i + 1] * inv, vals[i + 2] * inv)
              for i in range(0, count, 3)]
    return (w, h, pixels)


def tex_lookup(tex, u, v):
    w, h, pixels = tex
    x = int(math.floor(u * w))
    y = int(math.floor(v * h))
    if x < 0:
        x = 0
    elif x >= w:
        x = w - 1
    if y < 0:
        y = 0
    elif y >= h:
        y = h - 1
    return pixels[y * w + x]


# ---------------------------------------------------------- scene parsing

def parse_floats(args, count, key, lineno):
    if len(args) != count:
        raise SceneError('line %d: %s needs %d number(s)' % (lineno, key, count))
    out = []
    for a in args:
        try:
            v = float(a)
        except ValueError:
            raise SceneError('line %d: %r is not a number' % (lineno, a))
        if math.isnan(v) or math.isinf(v):
            raise SceneError('line %d: %r is not a finite number' % (lineno, a))
        out.append(v)
    return out


def normalize(v):
    l = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (v[0] / l, v[1] / l, v[2] / l)


def finish(section):
    if section is None:
        return
    kind = section['kind']
    if kind == 'camera':
        return
    if kind == 'light':
        if 'location' not in section:
            raise SceneError('light without location')
        section.setdefault('color', (1.0, 1.0, 1.0))
        return
    for need in ('center', 'dimension'):
        if need not in section:
            raise SceneError('%s without %s' % (kind, need))
    section.setdefault('color', (1.0, 1.0, 1.0))
    section.setdefault('reflectivity', 0.0)
    section.setdefault('texture', None)
    if kind == 'plane':
        for need in ('normal', 'headup'):
            if need not in section:
                raise SceneError('plane without %s' % need)
        nx, ny, nz = section['normal']
        if nx == 0 and ny == 0 and nz == 0:
            raise SceneError('plane normal is zero')
        n = normalize(section['normal'])
        u = section['headup']
        d = u[0] * n[0] + u[1] * n[1] + u[2] * n[2]
        u = (u[0] - d * n[0], u[1] - d * n[1], u[2] - d * n[2])
        ul = math.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
        hl = math.sqrt(sum(c * c for c in section['headup']))
        if ul <= 1e-9 * hl or hl == 0:
            raise SceneError('plane headup is zero or parallel to the normal')
        u = (u[0] / ul, u[1] / ul, u[2] / ul)
        # right = headup x normal
        r = (u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2], u[0] * n[1] - u[1] * n[0])
        section['normal'] = n
        section['headup'] = u
        section['right'] = r


def parse_scene(path):
    try:
        with open(path, 'r', encoding='utf-8', errors='replace') as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise SceneError('cannot open scene file %s: %s' % (path, e.strerror))
    folder = os.path.dirname(path)
    camera = None
    objects = []
    lights = []
    current = None
    for lineno, raw in enumerate(lines, 1):
        k = raw.find('#')
        line = raw[:k] if k >= 0 else raw
        parts = line.split()
        if not parts:
            continue
        key = parts[0].lower()
        args = parts[1:]
        if key == 'camera':
            if camera is not None:
                raise SceneError('line %d: more than one camera' % lineno)
            finish(current)
            if len(args) != 1:
                raise SceneError('line %d: camera needs one resolution' % lineno)
            try:
                camera = int(args[0])
            except ValueError:
                raise SceneError('line %d: bad camera resolution %r' % (lineno, args[0]))
            if camera <= 0 or camera > 20000:
                raise SceneError('line %d: bad camera resolution %d' % (lineno, camera))
            current = {'kind': 'camera'}
        elif key in ('sphere', 'plane', 'light'):
            if args:
                raise SceneError('line %d: unexpected text after %s' % (lineno, key))
            finish(current)
            current = {'kind': key}
            (lights if key == 'light' else objects).append(current)
        elif current is None or current['kind'] == 'camera':
            raise SceneError('line %d: unexpected %r' % (lineno, key))
        elif current['kind'] == 'light':
            if key == 'location':
                current['location'] = tuple(parse_floats(args, 3, key, lineno))
            elif key in ('color', 'colour'):
                c = tuple(parse_floats(args, 3, key, lineno))
                if min(c) < 0:
                    raise SceneError('line %d: negative light color' % lineno)
                current['color'] = c
            else:
                raise SceneError('line %d: unknown light attribute %r' % (lineno, key))
        else:
            kind = current['kind']
            if key == 'center':
                current['center'] = tuple(parse_floats(args, 3, key, lineno))
            elif key == 'dimension':
                if kind == 'sphere':
                    r = parse_floats(args, 1, key, lineno)[0]
                    if r <= 0:
                        raise SceneError('line %d: sphere dimension must be positive' % lineno)
                    current['dimension'] = r
                else:
                    w, h = parse_floats(args, 2, key, lineno)
                    if w <= 0 or h <= 0:
                        raise SceneError('line %d: plane dimensions must be positive' % lineno)
                    current['dimension'] = (w, h)
            elif key in ('color', 'colour'):
                c = tuple(parse_floats(args, 3, key, lineno))
                if min(c) < 0:
                    raise SceneError('line %d: negative color' % lineno)
                current['color'] = c
            elif key == 'reflectivity':
                r = parse_floats(args, 1, key, lineno)[0]
                if r < 0:
                    raise SceneError('line %d: negative reflectivity' % lineno)
                current['reflectivity'] = r
            elif key == 'texture':
                if len(args) != 1:
                    raise SceneError('line %d: texture needs one file name' % lineno)
                current['texture'] = load_ppm(os.path.join(folder, args[0]), args[0])
            elif kind == 'plane' and key in ('normal', 'headup'):
                current[key] = tuple(parse_floats(args, 3, key, lineno))
            else:
                raise SceneError('line %d: unknown %s attribute %r' % (lineno, kind, key))
    finish(current)
    if camera is None:
        raise SceneError('scene has no camera')
    return camera, objects, lights


# ------------------------------------------------------------- ray tracing

class Scene:
    def __init__(self, objects, lights):
        # spheres: (cx, cy, cz, r, r*r, index); planes: (cx,cy,cz,nx,ny,nz,d,rx,ry,rz,ux,uy,uz,hw,hh,index)
        self.objects = objects
        self.spheres = []
        self.planes = []
        for i, o in enumerate(objects):
            cx, cy, cz = o['center']
            if o['kind'] == 'sphere':
                r = o['dimension']
                self.spheres.append((cx, cy, cz, r, r * r, i))
            else:
                nx, ny, nz = o['normal']
                rx, ry, rz = o['right']
                ux, uy, uz = o['headup']
                w, h = o['dimension']
                self.planes.append((cx, cy, cz, nx, ny, nz, nx * cx + ny * cy + nz * cz,
                                    rx, ry, rz, ux, uy, uz, w / 2.0, h / 2.0, i))
        self.lights = [(l['location'], l['color']) for l in lights]

    def hit(self, ox, oy, oz, dx, dy, dz, tmax):
        """closest hit with T_MIN < t < tmax: returns (t, index) or None"""
        best = tmax
        idx = -1
        for cx, cy, cz, r, r2, i in self.spheres:
            # a = d.d = 1 (d is normalised)
            ex = ox - cx
            ey = oy - cy
            ez = oz - cz
            b = dx * ex + dy * ey + dz * ez          # half of b
            c = ex * ex + ey * ey + ez * ez - r2
            disc = b * b - c
            if disc < 0:
                continue
            s = math.sqrt(disc)
            t = -b - s
            if t <= T_MIN:
                t = -b + s
                if t <= T_MIN:
                    continue
            if t < best:
                best = t
                idx = i
        for (cx, cy, cz, nx, ny, nz, d, rx, ry, rz, ux, uy, uz, hw, hh, i) in self.planes:
            den = nx * dx + ny * dy + nz * dz
            if -1e-12 < den < 1e-12:
                continue
            t = (d - (nx * ox + ny * oy + nz * oz)) / den
            if t <= T_MIN or t >= best:
                continue
            qx = ox + t * dx - cx
            qy = oy + t * dy - cy
            qz = oz + t * dz - cz
            a = qx * rx + qy * ry + qz * rz
            if a > hw or a < -hw:
                continue
            a = qx * ux + qy * uy + qz * uz
            if a > hh or a < -hh:
                continue
            best = t
            idx = i
        if idx < 0:
            return None
        return best, idx

    def trace(self, ox, oy, oz, dx, dy, dz, depth):
        h = self.hit(ox, oy, oz, dx, dy, dz, math.inf)
        if h is None:
            return BACKGROUND
        t, i = h
        o = self.objects[i]
        px = ox + t * dx
        py = oy + t * dy
        pz = oz + t * dz
        tex = o['texture']
        if o['kind'] == 'sphere':
            cx, cy, cz = o['center']
            inv = 1.0 / o['dimension']
            nx = (px - cx) * inv
            ny = (py - cy) * inv
            nz = (pz - cz) * inv
            if tex is not None:
                # longitude / latitude mapping, y is the pole axis
                u = 0.5 - math.atan2(nz, nx) / (2 * math.pi)
                v = math.acos(max(-1.0, min(1.0, ny))) / math.pi
                base = tex_lookup(tex, u, v)
            else:
                base = o['color']
        else:
            nx, ny, nz = o['normal']
            if tex is not None:
                cx, cy, cz = o['center']
                qx = px - cx
                qy = py - cy
                qz = pz - cz
                rx, ry, rz = o['right']
                ux, uy, uz = o['headup']
                w, hh = o['dimension']
                u = (qx * rx + qy * ry + qz * rz) / w + 0.5
                v = 0.5 - (qx * ux + qy * uy + qz * uz) / hh
                base = tex_lookup(tex, u, v)
            else:
                base = o['color']
        if nx * dx + ny * dy + nz * dz > 0:
            nx = -nx
            ny = -ny
            nz = -nz
        br, bg, bb = base
        r = KA * br
        g = KA * bg
        b = KA * bb
        sx = px + EPS * nx
        sy = py + EPS * ny
        sz = pz + EPS * nz
        for (lx, ly, lz), (lr, lg, lb) in self.lights:
            Lx = lx - px
            Ly = ly - py
            Lz = lz - pz
            dist = math.sqrt(Lx * Lx + Ly * Ly + Lz * Lz)
            if dist == 0:
                continue
            Lx /= dist
            Ly /= dist
            Lz /= dist
            ndl = nx * Lx + ny * Ly + nz * Lz
            if ndl <= 0:
                continue
            if self.hit(sx, sy, sz, Lx, Ly, Lz, dist) is None:
                continue  # in shadow
            r += br * lr * ndl
            g += bg * lg * ndl
            b += bb * lb * ndl
        refl = o['reflectivity']
        if refl > 0 and depth < MAX_DEPTH:
            k = 2 * (dx * nx + dy * ny + dz * nz)
            rx = dx - k * nx
            ry = dy - k * ny
            rz = dz - k * nz
            l = math.sqrt(rx * rx + ry * ry + rz * rz)
            rr, rg, rb = self.trace(sx, sy, sz, rx / l, ry / l, rz / l, depth + 1)
            r += refl * rr
            g += refl * rg
            b += refl * rb
        return (r, g, b)


def to_byte(c):
    if c <= 0:
        return 0
    if c >= 1:
        return 255
    return int(c * 255 + 0.5)


def render(n, scene):
    rows = []
    trace = scene.trace
    sqrt = math.sqrt
    for j in range(n):
        y = 0.5 - (j + 0.5) / n
        row = []
        for i in range(n):
            x = -0.5 + (i + 0.5) / n
            l = sqrt(x * x + y * y + 1.0)
            r, g, b = trace(0.0, 0.0, 0.0, x / l, y / l, -1.0 / l, 0)
            row.append('%d %d %d' % (to_byte(r), to_byte(g), to_byte(b)))
        rows.append(' '.join(row))
    return rows


def main(argv):
    if len(argv) != 3:
        sys.stderr.write('usage: python3 tracer.py scene_description_file output_image\n')
        return 1
    try:
        n, objects, lights = parse_scene(argv[1])
    except SceneError as e:
        sys.stderr.write('error: %s\n' % e)
        return 1
    rows = render(n, Scene(objects, lights))
    try:
        with open(argv[2], 'w') as f:
            f.write('P3\n%d %d\n255\n' % (n, n))
            f.write('\n'.join(rows))
            f.write('\n')
    except OSError as e:
        sys.stderr.write('error: cannot write %s: %s\n' % (argv[2], e.strerror))
        try:
            os.remove(argv[2])
        except OSError:
            pass
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
