#!/usr/bin/env python3
"""HW4 - a simple ray tracer.

    python3 tracer.py scene.txt out.ppm

One ray per pixel, one shadow ray per light, recursive reflection.
Output is a binary PPM (P6) of camera N x N pixels.
"""
import math
import os
import sys

MAX_DEPTH = 4
AMBIENT = 0.1


def normalize(x, y, z):
    l = math.sqrt(x * x + y * y + z * z)
    if l == 0:
        return x, y, z
    return x / l, y / l, z / l


def read_ppm(path):
    """Read a P3 or P6 texture. Returns (width, height, list of (r,g,b) floats)."""
    with open(path, 'rb') as f:
        data = f.read()
    tokens = []
    pos = 0
    while len(tokens) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b'#':
            while data[pos:pos + 1] not in (b'\n', b''):
                pos += 1
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos])
    magic, w, h, maxval = tokens[0], int(tokens[1]), int(tokens[2]), int(tokens[3])
    if magic == b'P6':
        pos += 1
        if maxval < 256:
            vals = data[pos:pos + w * h * 3]
        else:
            raw = data[pos:pos + w * h * 6]
            vals = [raw[i] * 256 + raw[i + 1] for i in range(0, len(raw), 2)]
    elif magic == b'P3':
        vals = [int(v) for v in data[pos:].split()[:w * h * 3]]
    else:
        raise ValueError(path + ': not a PPM file')
    pixels = []
    for i in range(w * h):
        pixels.append((vals[3 * i] / maxval, vals[3 * i + 1] / maxval, vals[3 * i + 2] / maxval))
    return w, h, pixels


class Obj:
    def __init__(self, kind):
        self.kind = kind          # 'sphere' or 'plane'
        self.dim = []
        self.center = (0.0, 0.0, 0.0)
        self.color = (1.0, 1.0, 1.0)
        self.normal = (0.0, 0.0, 1.0)
        self.headup = (0.0, 1.0, 0.0)
        self.refl = 0.0
        self.texture = None


class Light:
    def __init__(self):
        self.location = (0.0, 0.0, 0.0)
        self.color = (1.0, 1.0, 1.0)


def parse(path):
    size = 0
    objects = []
    lights = []
    current = None
    with open(path) as f:
        for line in f:
            words = line.split('#')[0].split()
            if not words:
                continue
            key, args = words[0], words[1:]
            if key == 'camera':
                size = int(float(args[0]))
                current = None
            elif key in ('sphere', 'plane'):
                current = Obj(key)
                objects.append(current)
            elif key == 'light':
                current = Light()
                lights.append(current)
            elif key == 'texture':
                current.texture = os.path.join(os.path.dirname(path), args[0])
            else:
                nums = tuple(float(a) for a in args)
                if key == 'dimension':
                    current.dim = list(nums)
                elif key == 'center':
                    current.center = nums
                elif key == 'color':
                    current.color = nums
                elif key == 'normal':
                    current.normal = nums
                elif key == 'headup':
                    current.headup = nums
                elif key == 'reflectivity':
                    current.refl = nums[0]
                elif key == 'location':
                    current.location = nums
                else:
                    print('ignoring', key, file=sys.stderr)
    return size, objects, lights


class Scene:
    def __init__(self, path):
        self.size, objects, lights = parse(path)
        self.spheres = []   # (cx, cy, cz, r, obj)
        self.planes = []    # (nx, ny, nz, d, obj)
        self.lights = [(l.location, l.color) for l in lights]
        textures = {}
        for o in objects:
            if o.texture:
                if o.texture not in textures:
                    textures[o.texture] = read_ppm(o.texture)
                o.tex = textures[o.texture]
            else:
                o.tex = None
            if o.kind == 'sphere':
                cx, cy, cz = o.center
                o.radius = o.dim[0]
                self.spheres.append((cx, cy, cz, o.radius * o.radius, o))
            else:
                n = normalize(*o.normal)
                o.n = n
                hx, hy, hz = o.headup
                k = hx * n[0] + hy * n[1] + hz * n[2]
                up = normalize(hx - k * n[0], hy - k * n[1], hz - k * n[2])
                o.up = up
                # right = up x n, so the texture is not mirrored seen from the front
                o.right = (up[1] * n[2] - up[2] * n[1],
                           up[2] * n[0] - up[0] * n[2],
                           up[0] * n[1] - up[1] * n[0])
                o.w, o.h = o.dim[0], o.dim[1]
                d = -(n[0] * o.center[0] + n[1] * o.center[1] + n[2] * o.center[2])
                self.planes.append((n[0], n[1], n[2], d, o))

    def hit(self, ox, oy, oz, dx, dy, dz, tmin, tmax):
        """Closest hit along a ray with unit direction. Returns (t, obj) or (tmax, None)."""
        best = tmax
        found = None
        for cx, cy, cz, r2, o in self.spheres:
            lx = cx - ox
            ly = cy - oy
            lz = cz - oz
            tca = lx * dx + ly * dy + lz * dz
            d2 = lx * lx + ly * ly + lz * lz - tca * tca
            if d2 > r2:
                continue
            thc = math.sqrt(r2 - d2)
            t = tca - thc
            if t <= tmin:
                t = tca + thc
            if tmin < t < best:
                best = t
                found = o
        for nx, ny, nz, d, o in self.planes:
            dn = nx * dx + ny * dy + nz * dz
            if dn == 0:
                continue
            t = -(nx * ox + ny * oy + nz * oz + d) / dn
            if tmin < t < best:
                px = ox + t * dx - o.center[0]
                py = oy + t * dy - o.center[1]
                pz = oz + t * dz - o.center[2]
                u = px * o.right[0] + py * o.right[1] + pz * o.right[2]
                v = px * o.up[0] + py * o.up[1] + pz * o.up[2]
                if abs(u) <= o.w / 2 and abs(v) <= o.h / 2:
                    best = t
                    found = o
        return best, found


def surface_color(o, px, py, pz):
    if o.tex is None:
        return o.color
    w, h, pixels = o.tex
    qx, qy, qz = px - o.center[0], py - o.center[1], pz - o.center[2]
    if o.kind == 'plane':
        u = (qx * o.right[0] + qy * o.right[1] + qz * o.right[2]) / o.w + 0.5
        v = 0.5 - (qx * o.up[0] + qy * o.up[1] + qz * o.up[2]) / o.h   # row 0 is towards headup
    else:
        r = o.radius
        u = 0.5 + math.atan2(qz / r, qx / r) / (2 * math.pi)
        v = 0.5 - math.asin(max(-1.0, min(1.0, qy / r))) / math.pi    # north pole = top row
    i = min(w - 1, max(0, int(u * w)))
    j = min(h - 1, max(0, int(v * h)))
    return pixels[j * w + i]


def trace(scene, ox, oy, oz, dx, dy, dz, depth):
    scale = 1.0 + math.sqrt(ox * ox + oy * oy + oz * oz)
    t, o = scene.hit(ox, oy, oz, dx, dy, dz, 1e-7 * scale, 1e300)
    if o is None:
        return 0.0, 0.0, 0.0
    px, py, pz = ox + t * dx, oy + t * dy, oz + t * dz
    if o.kind == 'sphere':
        nx, ny, nz = (px - o.center[0]) / o.radius, (py - o.center[1]) / o.radius, (pz - o.center[2]) / o.radius
    else:
        nx, ny, nz = o.n
    if nx * dx + ny * dy + nz * dz > 0:      # seen from behind / from inside
        nx, ny, nz = -nx, -ny, -nz
    cr, cg, cb = surface_color(o, px, py, pz)
    r, g, b = AMBIENT * cr, AMBIENT * cg, AMBIENT * cb

    # shadow rays leave from slightly above the surface
    eps = 1e-7 * (1.0 + math.sqrt(px * px + py * py + pz * pz))
    sx, sy, sz = px + eps * nx, py + eps * ny, pz + eps * nz
    for (qx, qy, qz), (lr, lg, lb) in scene.lights:
        lx, ly, lz = qx - px, qy - py, qz - pz
        dist = math.sqrt(lx * lx + ly * ly + lz * lz)
        if dist == 0:
            continue
        lx, ly, lz = lx / dist, ly / dist, lz / dist
        cos = nx * lx + ny * ly + nz * lz
        if cos <= 0:
            continue
        # shadow ray from the lifted point straight to the light
        ex, ey, ez = qx - sx, qy - sy, qz - sz
        sd = math.sqrt(ex * ex + ey * ey + ez * ez)
        ts, blocker = scene.hit(sx, sy, sz, ex / sd, ey / sd, ez / sd, 0.0, sd - eps)
        if blocker is not None:
            continue
        r += cr * lr * cos
        g += cg * lg * cos
        b += cb * lb * cos

    k = o.refl
    if k > 0 and depth < MAX_DEPTH:
        # r = 2 (n.v) n - v
        vx, vy, vz = ox - px, oy - py, oz - pz     # towards the viewer
        nv = nx * vx + ny * vy + nz * vz
        rx, ry, rz = 2 * nv * nx - vx, 2 * nv * ny - vy, 2 * nv * nz - vz
        rr, rg, rb = trace(scene, px, py, pz, rx, ry, rz, depth + 1)
        r += k * rr
        g += k * rg
        b += k * rb
    return r, g, b


def to_byte(c):
    if c <= 0:
        return 0
    if c >= 1:
        return 255
    return int(c * 255)


def main():
    if len(sys.argv) < 3:
        print('usage: tracer.py scene output.ppm', file=sys.stderr)
        sys.exit(1)
    scene = Scene(sys.argv[1])
    n = scene.size
    out = bytearray()
    for row in range(n):
        y = 0.5 - (row + 0.5) / n
        for col in range(n):
            x = -0.5 + (col + 0.5) / n
            l = math.sqrt(x * x + y * y + 1.0)
            r, g, b = trace(scene, 0.0, 0.0, 0.0, x / l, y / l, -1.0 / l, 0)
            out.append(to_byte(r))
            out.append(to_byte(g))
            out.append(to_byte(b))
    with open(sys.argv[2], 'wb') as f:
        f.write(b'P6\n%d %d\n255\n' % (n, n))
        f.write(out)


if __name__ == '__main__':
    main()
