#!/usr/bin/env python3
"""HW4 ray tracer in plain Python 3 (standard library only).

usage: python3 tracer.py scene_description_file output_image

My choices where the handout leaves things open:
  * sphere "dimension" = radius; plane "dimension w h" = full width along
    (headup x normal) and full height along headup; the plane is a finite rectangle
  * one ray per pixel through the pixel centre; image plane z = -1, 1 x 1
  * local model: 0.1 * colour (ambient) + sum over lights that are not blocked of
    colour * light colour * max(0, N.L)   (no highlight)
  * reflection: local + reflectivity * reflected colour, at most 4 bounces
  * secondary rays start 1e-5 along the normal; hits need t > 0
  * texture (P6 or P3) replaces the colour, nearest texel
  * sphere texture: u = 0.5 + atan2(x, z) / 2pi (texture centre faces +z,
    seam at the back), v = acos(y) / pi (top row at the north pole)
  * plane texture: stretched once over the rectangle, top row at the headup edge
  * output P6, clamp to [0, 1], value * 255 truncated
"""
import math
import os
import sys

KA = 0.1
MAX_DEPTH = 4
EPS = 1e-5


def read_ppm(path):
    with open(path, 'rb') as f:
        data = f.read()
    pos = 0
    tokens = []
    # header: magic, width, height, maxval (comments start with #)
    while len(tokens) < 4:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b'#':
            while pos < len(data) and data[pos:pos + 1] != b'\n':
                pos += 1
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos])
    magic = tokens[0]
    w, h, maxv = int(tokens[1]), int(tokens[2]), int(tokens[3])
    if magic == b'P6':
        pos += 1
        if maxv < 256:
            raw = data[pos:pos + w * h * 3]
            vals = list(raw)
        else:
            vals = [data[pos + 2 * k] * 256 + data[pos + 2 * k + 1] for k in range(w * h * 3)]
    elif magic == b'P3':
        body = data[pos:].split(b'\n')
        words = []
        for line in body:
            line = line.split(b'#')[0]
            words.extend(line.split())
        vals = [int(x) for x in words[:w * h * 3]]
    else:
        raise ValueError('not a PPM file: %s' % path)
    s = 1.0 / maxv
    pix = [(vals[3 * k] * s, vals[3 * k + 1] * s, vals[3 * k + 2] * s) for k in range(w * h)]
    return (w, h, pix)


def normalize(v):
    l = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if l == 0:
        return v
    return (v[0] / l, v[1] / l, v[2] / l)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


class Obj:
    __slots__ = ('kind', 'center', 'radius', 'w', 'h', 'normal', 'headup', 'up', 'right',
                 'color', 'refl', 'tex', 'pd')

    def __init__(self, kind):
        self.kind = kind
        self.center = (0.0, 0.0, 0.0)
        self.radius = 1.0
        self.w = 1.0
        self.h = 1.0
        self.normal = (0.0, 1.0, 0.0)
        self.headup = (0.0, 0.0, 1.0)
        self.color = (1.0, 1.0, 1.0)
        self.refl = 0.0
        self.tex = None


def parse(path):
    res = 256
    objs = []
    lights = []
    cur = None
    base = os.path.dirname(os.path.abspath(path))
    with open(path) as f:
        for line in f:
            line = line.split('#')[0]
            parts = line.split()
            if not parts:
                continue
            key = parts[0].lower()
            args = parts[1:]
            if key == 'camera':
                res = int(float(args[0]))
                cur = None
            elif key in ('sphere', 'plane'):
                cur = Obj(key)
                objs.append(cur)
            elif key == 'light':
                cur = {'location': (0.0, 0.0, 0.0), 'color': (1.0, 1.0, 1.0)}
                lights.append(cur)
            elif cur is None:
                print('warning: ignoring line', line.strip(), file=sys.stderr)
            elif isinstance(cur, dict):
                if key == 'location':
                    cur['location'] = tuple(float(a) for a in args[:3])
                elif key in ('color', 'colour'):
                    cur['color'] = tuple(float(a) for a in args[:3])
            else:
                if key == 'dimension':
                    if cur.kind == 'sphere':
                        cur.radius = float(args[0])
                    else:
                        cur.w = float(args[0])
                        cur.h = float(args[1]) if len(args) > 1 else cur.w
                elif key in ('center', 'centre'):
                    cur.center = tuple(float(a) for a in args[:3])
                elif key in ('color', 'colour'):
                    cur.color = tuple(float(a) for a in args[:3])
                elif key == 'reflectivity':
                    cur.refl = float(args[0])
                elif key == 'normal':
                    cur.normal = tuple(float(a) for a in args[:3])
                elif key == 'headup':
                    cur.headup = tuple(float(a) for a in args[:3])
                elif key == 'texture':
                    name = args[0]
                    for cand in (os.path.join(base, name), name):
                        try:
                            cur.tex = read_ppm(cand)
                            break
                        except (OSError, ValueError, IndexError):
                            pass
                    if cur.tex is None:
                        print('warning: cannot read texture', name, file=sys.stderr)
    for o in objs:
        if o.kind == 'plane':
            n = normalize(o.normal)
            o.normal = n
            hu = o.headup
            k = hu[0] * n[0] + hu[1] * n[1] + hu[2] * n[2]
            up = (hu[0] - k * n[0], hu[1] - k * n[1], hu[2] - k * n[2])
            if up[0] * up[0] + up[1] * up[1] + up[2] * up[2] < 1e-18:
                a = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
                k = a[0] * n[0] + a[1] * n[1] + a[2] * n[2]
                up = (a[0] - k * n[0], a[1] - k * n[1], a[2] - k * n[2])
            o.up = normalize(up)
            o.right = cross(o.up, n)
            # plane equation a x + b y + c z + d = 0
            o.pd = -(n[0] * o.center[0] + n[1] * o.center[1] + n[2] * o.center[2])
    return res, objs, lights


def hit(o, ox, oy, oz, dx, dy, dz):
    """t of the nearest hit in front of the origin (t > 0), or -1; d is unit length."""
    if o.kind == 'sphere':
        c = o.center
        ex = ox - c[0]
        ey = oy - c[1]
        ez = oz - c[2]
        b = dx * ex + dy * ey + dz * ez
        cc = ex * ex + ey * ey + ez * ez - o.radius * o.radius
        disc = b * b - cc
        if disc < 0:
            return -1.0
        sq = math.sqrt(disc)
        t = -b - sq
        if t > 0:
            return t
        t = -b + sq
        if t > 0:
            return t
        return -1.0
    n = o.normal
    den = n[0] * dx + n[1] * dy + n[2] * dz
    if den == 0:
        return -1.0
    t = -(n[0] * ox + n[1] * oy + n[2] * oz + o.pd) / den
    if t <= 0:
        return -1.0
    c = o.center
    qx = ox + t * dx - c[0]
    qy = oy + t * dy - c[1]
    qz = oz + t * dz - c[2]
    r = o.right
    if abs(qx * r[0] + qy * r[1] + qz * r[2]) > o.w * 0.5:
        return -1.0
    u = o.up
    if abs(qx * u[0] + qy * u[1] + qz * u[2]) > o.h * 0.5:
        return -1.0
    return t


def surface_color(o, px, py, pz):
    if o.tex is None:
        return o.color
    tw, th, pix = o.tex
    c = o.center
    qx = px - c[0]
    qy = py - c[1]
    qz = pz - c[2]
    if o.kind == 'plane':
        r = o.right
        u = o.up
        s = (qx * r[0] + qy * r[1] + qz * r[2]) / o.w + 0.5
        t = 0.5 - (qx * u[0] + qy * u[1] + qz * u[2]) / o.h
    else:
        inv = 1.0 / math.sqrt(qx * qx + qy * qy + qz * qz)
        nx, ny, nz = qx * inv, qy * inv, qz * inv
        s = 0.5 + math.atan2(nx, nz) / (2 * math.pi)
        t = math.acos(max(-1.0, min(1.0, ny))) / math.pi
    i = int(s * tw)
    j = int(t * th)
    if i < 0:
        i = 0
    elif i >= tw:
        i = tw - 1
    if j < 0:
        j = 0
    elif j >= th:
        j = th - 1
    return pix[j * tw + i]


def nearest(objs, ox, oy, oz, dx, dy, dz):
    best = 1e300
    bo = None
    for o in objs:
        t = hit(o, ox, oy, oz, dx, dy, dz)
        if 0 < t < best:
            best = t
            bo = o
    return best, bo


def trace(objs, lights, ox, oy, oz, dx, dy, dz, depth):
    t, o = nearest(objs, ox, oy, oz, dx, dy, dz)
    if o is None:
        return (0.0, 0.0, 0.0)
    px = ox + t * dx
    py = oy + t * dy
    pz = oz + t * dz
    if o.kind == 'sphere':
        c = o.center
        inv = 1.0 / o.radius
        nx = (px - c[0]) * inv
        ny = (py - c[1]) * inv
        nz = (pz - c[2]) * inv
    else:
        nx, ny, nz = o.normal
    if nx * dx + ny * dy + nz * dz > 0:
        # seen from behind (planes) or from inside: use the side facing the ray
        nx, ny, nz = -nx, -ny, -nz
    cr, cg, cb = surface_color(o, px, py, pz)
    r = KA * cr
    g = KA * cg
    b = KA * cb
    sx = px + EPS * nx
    sy = py + EPS * ny
    sz = pz + EPS * nz
    for light in lights:
        lx, ly, lz = light['location']
        lx -= px
        ly -= py
        lz -= pz
        d2 = lx * lx + ly * ly + lz * lz
        dist = math.sqrt(d2)
        lx /= dist
        ly /= dist
        lz /= dist
        ndl = nx * lx + ny * ly + nz * lz
        if ndl <= 0:
            continue
        blocked = False
        for other in objs:
            ts = hit(other, sx, sy, sz, lx, ly, lz)
            if 0 < ts < d2:
                blocked = True
                break
        if blocked:
            continue
        lr, lg, lb = light['color']
        r += cr * lr * ndl
        g += cg * lg * ndl
        b += cb * lb * ndl
    if o.refl > 0 and depth < MAX_DEPTH:
        k = 2 * (nx * dx + ny * dy + nz * dz)
        rx = dx - k * nx
        ry = dy - k * ny
        rz = dz - k * nz
        rr, rg, rb = trace(objs, lights, sx, sy, sz, rx, ry, rz, depth + 1)
        r += o.refl * rr
        g += o.refl * rg
        b += o.refl * rb
    return (r, g, b)


def to_byte(v):
    if v <= 0:
        return 0
    if v >= 1:
        return 255
    return int(v * 255)


def main():
    if len(sys.argv) < 3:
        print('usage: python3 tracer.py scene_description_file output_image', file=sys.stderr)
        sys.exit(1)
    res, objs, lights = parse(sys.argv[1])
    out = bytearray()
    inv = 1.0 / res
    for j in range(res):
        y = 0.5 - (j + 0.5) * inv
        for i in range(res):
            x = -0.5 + (i + 0.5) * inv
            l = math.sqrt(x * x + y * y + 1.0)
            r, g, b = trace(objs, lights, 0.0, 0.0, 0.0, x / l, y / l, -1.0 / l, 0)
            out.append(to_byte(r))
            out.append(to_byte(g))
            out.append(to_byte(b))
    with open(sys.argv[2], 'wb') as f:
        f.write(b'P6\n%d %d\n255\n' % (res, res))
        f.write(bytes(out))


if __name__ == '__main__':
    main()
