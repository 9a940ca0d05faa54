/* HW4 ray tracer in C.
 * usage: ./tracer scene_description_file output_image
 * Writes a binary PPM (P6, maxval 255) whatever the output name is.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <ctype.h>

typedef struct { double x, y, z; } vec;

static vec v3(double x, double y, double z) { vec v = {x, y, z}; return v; }
static vec vadd(vec a, vec b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec vsub(vec a, vec b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec vscale(vec a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static vec vmul(vec a, vec b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static double vdot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec vcross(vec a, vec b) { return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x); }
static double vlen(vec a) { return sqrt(vdot(a, a)); }
static vec vnorm(vec a) { double l = vlen(a); return vscale(a, 1.0 / l); }

static void die(const char *msg, const char *arg)
{
    if (arg) fprintf(stderr, "tracer: %s: %s\n", msg, arg);
    else fprintf(stderr, "tracer: %s\n", msg);
    exit(1);
}

/* ------------------------------------------------------------ textures */
typedef struct { int w, h; float *px; } texture;

static const unsigned char *pp_data; static size_t pp_len, pp_pos;

static void pp_skip(void)
{
    while (pp_pos < pp_len) {
        unsigned char c = pp_data[pp_pos];
        if (c == '#') { while (pp_pos < pp_len && pp_data[pp_pos] != '\n' && pp_data[pp_pos] != '\r') pp_pos++; }
        else if (isspace(c)) pp_pos++;
        else break;
    }
}

static long pp_int(const char *path)
{
    long v = 0; int any = 0;
    pp_skip();
    while (pp_pos < pp_len && isdigit(pp_data[pp_pos])) {
        v = v * 10 + (pp_data[pp_pos] - '0');
        if (v > 100000000L) die("texture number too large", path);
        pp_pos++; any = 1;
    }
    if (!any) die("malformed PPM texture", path);
    return v;
}

static texture *load_ppm(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) die("cannot open texture", path);
    size_t cap = 1 << 16, len = 0; unsigned char *buf = malloc(cap);
    size_t r;
    while ((r = fread(buf + len, 1, cap - len, f)) > 0) {
        len += r;
        if (len == cap) { cap *= 2; buf = realloc(buf, cap); }
    }
    fclose(f);
    pp_data = buf; pp_len = len; pp_pos = 0;
    if (len < 2 || buf[0] != 'P' || (buf[1] != '6' && buf[1] != '3')) die("texture is not a P3/P6 PPM", path);
    int binary = buf[1] == '6';
    pp_pos = 2;
    long w = pp_int(path), h = pp_int(path), maxv = pp_int(path);
    if (w <= 0 || h <= 0 || maxv <= 0 || maxv > 65535 || w * h > 100000000L) die("bad PPM header", path);
    texture *t = malloc(sizeof *t);
    t->w = (int)w; t->h = (int)h;
    size_t n = (size_t)w * h * 3;
    t->px = malloc(n * sizeof(float));
    if (binary) {
        pp_pos++;
        int bpc = maxv < 256 ? 1 : 2;
        if (pp_pos + n * bpc > len) die("truncated PPM texture", path);
        for (size_t i = 0; i < n; i++) {
            long v = bpc == 1 ? buf[pp_pos + i] : (buf[pp_pos + 2 * i] << 8 | buf[pp_pos + 2 * i + 1]);
            float fv = (float)v / (float)maxv;
            t->px[i] = fv > 1 ? 1 : fv;
        }
    } else {
        for (size_t i = 0; i < n; i++) {
            long v = pp_int(path);
            float fv = (float)v / (float)maxv;
            t->px[i] = fv > 1 ? 1 : fv;
        }
    }
    free(buf);
    return t;
}

static vec tex_lookup(const texture *t, double u, double v)
{
    u -= floor(u); v -= floor(v);
    int i = (int)(u * t->w), j = (int)(v * t->h);
    if (i >= t->w) i = t->w - 1;
    if (j >= t->h) j = t->h - 1;
    if (i < 0) i = 0;
    if (j < 0) j = 0;
    const float *p = t->px + 3 * ((size_t)j * t->w + i);
    return v3(p[0], p[1], p[2]);
}

/* ------------------------------------------------------------ scene */
enum { SPHERE, PLANE };

typedef struct {
    int kind;
    vec center, color;
    double refl;
    texture *tex;
    double radius;           /* sphere */
    double dim_up, dim_side; /* plane: first number along headup, second across */
    vec normal, headup, up, side;
} object;

typedef struct { vec pos, color; } light;

static int res = -1;
static object *objs; static int nobj, capobj;
static light *lights; static int nlight, caplight;

/* Replace every Unicode white-space character (UTF-8 encoded) by a plain space. */
static void blank_unicode_space(unsigned char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        unsigned c = s[i];
        if (c < 0x80) { if (c == '\v' || c == '\f') s[i] = ' '; continue; }
        unsigned cp = 0; int len = 0;
        if ((c & 0xE0) == 0xC0 && i + 1 < n) { cp = (c & 0x1F) << 6 | (s[i + 1] & 0x3F); len = 2; }
        else if ((c & 0xF0) == 0xE0 && i + 2 < n) { cp = (c & 0x0F) << 12 | (s[i + 1] & 0x3F) << 6 | (s[i + 2] & 0x3F); len = 3; }
        else if ((c & 0xF8) == 0xF0 && i + 3 < n) { len = 4; cp = 0x10000; }
        else continue;
        int ws = cp == 0x85 || cp == 0xA0 || cp == 0x1680 || (cp >= 0x2000 && cp <= 0x200B) ||
                 cp == 0x2028 || cp == 0x2029 || cp == 0x202F || cp == 0x205F || cp == 0x3000 || cp == 0xFEFF;
        if (ws) for (int k = 0; k < len; k++) s[i + k] = ' ';
        i += len - 1;
    }
}

static char **tok; static int ntok, tpos;

static int is_number(const char *s)
{
    const char *p = s; int digits = 0;
    if (*p == '+' || *p == '-') p++;
    while (isdigit((unsigned char)*p)) { p++; digits++; }
    if (*p == '.') { p++; while (isdigit((unsigned char)*p)) { p++; digits++; } }
    if (!digits) return 0;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-') p++;
        if (!isdigit((unsigned char)*p)) return 0;
        while (isdigit((unsigned char)*p)) p++;
    }
    return *p == 0;
}

static double number(const char *what)
{
    if (tpos >= ntok) die("missing number after", what);
    const char *s = tok[tpos++];
    if (!is_number(s)) die("not a number", s);
    double v = strtod(s, NULL);
    if (!isfinite(v)) die("number out of range", s);
    return v;
}

static vec vector3(const char *what)
{
    double a = number(what), b = number(what), c = number(what);
    return v3(a, b, c);
}

static object *new_object(int kind)
{
    if (nobj == capobj) { capobj = capobj ? capobj * 2 : 8; objs = realloc(objs, capobj * sizeof *objs); }
    object *o = &objs[nobj++];
    memset(o, 0, sizeof *o);
    o->kind = kind;
    o->color = v3(1, 1, 1);
    o->radius = 1;
    o->dim_up = o->dim_side = 1;
    o->normal = v3(0, 0, 1);
    o->headup = v3(0, 1, 0);
    return o;
}

static void parse(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) die("cannot open scene file", path);
    size_t cap = 4096, len = 0; unsigned char *buf = malloc(cap + 1);
    size_t r;
    while ((r = fread(buf + len, 1, cap - len, f)) > 0) {
        len += r;
        if (len == cap) { cap *= 2; buf = realloc(buf, cap + 1); }
    }
    fclose(f);
    buf[len] = 0;
    for (size_t i = 0; i < len; i++) if (buf[i] == 0) die("scene file contains a NUL byte", path);
    blank_unicode_space(buf, len);

    /* directory of the scene, for texture paths */
    char dir[4096] = "";
    const char *slash = strrchr(path, '/');
    if (slash && (size_t)(slash - path) < sizeof dir - 1) { memcpy(dir, path, slash - path + 1); dir[slash - path + 1] = 0; }

    int tcap = 256; tok = malloc(tcap * sizeof *tok); ntok = 0;
    for (char *p = strtok((char *)buf, " \t\r\n"); p; p = strtok(NULL, " \t\r\n")) {
        if (ntok == tcap) { tcap *= 2; tok = realloc(tok, tcap * sizeof *tok); }
        tok[ntok++] = p;
    }

    object *cur = NULL; light *curl = NULL;
    tpos = 0;
    while (tpos < ntok) {
        const char *k = tok[tpos++];
        if (!strcmp(k, "camera")) {
            if (res > 0) die("more than one camera line", NULL);
            double v = number("camera");
            if (v != floor(v) || v < 1 || v > 20000) die("bad camera resolution", tok[tpos - 1]);
            res = (int)v; cur = NULL; curl = NULL;
        } else if (!strcmp(k, "sphere")) { cur = new_object(SPHERE); curl = NULL; }
        else if (!strcmp(k, "plane")) { cur = new_object(PLANE); curl = NULL; }
        else if (!strcmp(k, "light")) {
            if (nlight == caplight) { caplight = caplight ? caplight * 2 : 8; lights = realloc(lights, caplight * sizeof *lights); }
            curl = &lights[nlight++]; curl->pos = v3(0, 0, 0); curl->color = v3(1, 1, 1); cur = NULL;
        } else if (!strcmp(k, "dimension")) {
            if (!cur) die("'dimension' outside an object", NULL);
            if (cur->kind == SPHERE) {
                cur->radius = number(k);
                if (cur->radius <= 0) die("sphere dimension must be positive", NULL);
            } else {
                cur->dim_up = number(k); cur->dim_side = number(k);
                if (cur->dim_up <= 0 || cur->dim_side <= 0) die("plane dimensions must be positive", NULL);
            }
        } else if (!strcmp(k, "center")) {
            if (!cur) die("'center' outside an object", NULL);
            cur->center = vector3(k);
        } else if (!strcmp(k, "color")) {
            if (cur) cur->color = vector3(k);
            else if (curl) curl->color = vector3(k);
            else die("'color' outside an object or light", NULL);
        } else if (!strcmp(k, "reflectivity")) {
            if (!cur) die("'reflectivity' outside an object", NULL);
            cur->refl = number(k);
        } else if (!strcmp(k, "texture")) {
            if (!cur) die("'texture' outside an object", NULL);
            if (tpos >= ntok) die("missing texture file name", NULL);
            const char *name = tok[tpos++];
            char full[8192];
            if (name[0] == '/') snprintf(full, sizeof full, "%s", name);
            else snprintf(full, sizeof full, "%s%s", dir, name);
            cur->tex = load_ppm(full);
        } else if (!strcmp(k, "normal")) {
            if (!cur || cur->kind != PLANE) die("'normal' outside a plane", NULL);
            cur->normal = vector3(k);
        } else if (!strcmp(k, "headup")) {
            if (!cur || cur->kind != PLANE) die("'headup' outside a plane", NULL);
            cur->headup = vector3(k);
        } else if (!strcmp(k, "location")) {
            if (!curl) die("'location' outside a light", NULL);
            curl->pos = vector3(k);
        } else {
            die("unknown keyword", k);
        }
    }
    if (res <= 0) die("scene has no camera line", NULL);

    for (int i = 0; i < nobj; i++) {
        object *o = &objs[i];
        if (o->kind != PLANE) continue;
        if (vlen(o->normal) < 1e-12) die("plane normal is zero", NULL);
        o->normal = vnorm(o->normal);
        vec u = vsub(o->headup, vscale(o->normal, vdot(o->headup, o->normal)));
        if (vlen(u) < 1e-9) {
            vec ref = fabs(o->normal.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
            u = vsub(ref, vscale(o->normal, vdot(ref, o->normal)));
        }
        o->up = vnorm(u);
        o->side = vnorm(vcross(o->normal, o->up));
    }
}

/* ------------------------------------------------------------ geometry */
static double intersect(const object *o, vec org, vec dir, double tmin)
{
    if (o->kind == SPHERE) {
        vec oc = vsub(org, o->center);
        double a = vdot(dir, dir), b = 2 * vdot(dir, oc), c = vdot(oc, oc) - o->radius * o->radius;
        double disc = b * b - 4 * a * c;
        if (disc < 0) return -1;
        double d = sqrt(disc);
        double t = (-b - d) / (2 * a);
        if (t > tmin) return t;
        t = (-b + d) / (2 * a);
        if (t > tmin) return t;
        return -1;
    } else {
        double den = vdot(o->normal, dir);
        if (fabs(den) < 1e-12) return -1;
        double t = vdot(o->normal, vsub(o->center, org)) / den;
        if (t <= tmin) return -1;
        vec q = vsub(vadd(org, vscale(dir, t)), o->center);
        if (fabs(vdot(q, o->up)) > o->dim_up / 2 || fabs(vdot(q, o->side)) > o->dim_side / 2) return -1;
        return t;
    }
}

static vec surface_color(const object *o, vec p)
{
    if (!o->tex) return o->color;
    double u, v;
    if (o->kind == SPHERE) {
        vec n = vnorm(vsub(p, o->center));
        double ny = n.y > 1 ? 1 : n.y < -1 ? -1 : n.y;
        u = 0.5 - atan2(n.z, n.x) / (2 * M_PI);
        v = 0.5 - asin(ny) / M_PI;
    } else {
        vec q = vsub(p, o->center);
        u = 0.5 + vdot(q, o->side) / o->dim_side;
        v = 0.5 - vdot(q, o->up) / o->dim_up;
    }
    return vmul(tex_lookup(o->tex, u, v), o->color);
}

#define KA 0.15
#define KD 0.9
#define EPS 1e-4
#define MAX_DEPTH 8

static int closest(vec org, vec dir, double tmin, double *tout)
{
    int best = -1; double bt = INFINITY;
    for (int i = 0; i < nobj; i++) {
        double t = intersect(&objs[i], org, dir, tmin);
        if (t > tmin && t < bt) { bt = t; best = i; }
    }
    *tout = bt;
    return best;
}

static int in_shadow(vec p, vec l, double dist)
{
    for (int i = 0; i < nobj; i++) {
        double t = intersect(&objs[i], p, l, EPS);
        if (t > EPS && t < dist) return 1;
    }
    return 0;
}

static vec trace(vec org, vec dir, int depth, double tmin)
{
    double t;
    int hi = closest(org, dir, tmin, &t);
    if (hi < 0) return v3(0, 0, 0);
    const object *o = &objs[hi];
    vec p = vadd(org, vscale(dir, t));
    vec n = o->kind == SPHERE ? vnorm(vsub(p, o->center)) : o->normal;
    if (vdot(n, dir) > 0) n = vscale(n, -1);
    vec base = surface_color(o, p);
    vec col = vscale(base, KA);
    for (int i = 0; i < nlight; i++) {
        vec l = vsub(lights[i].pos, p);
        double dist = vlen(l);
        if (dist < 1e-12) continue;
        l = vscale(l, 1.0 / dist);
        double ndl = vdot(n, l);
        if (ndl <= 0) continue;
        if (in_shadow(p, l, dist)) continue;
        col = vadd(col, vscale(vmul(base, lights[i].color), KD * ndl));
    }
    if (o->refl > 0 && depth < MAX_DEPTH) {
        vec r = vnorm(vsub(dir, vscale(n, 2 * vdot(dir, n))));
        vec rc = trace(p, r, depth + 1, EPS);
        col = vadd(vscale(col, 1 - o->refl), vscale(rc, o->refl));
    }
    return col;
}

static unsigned char to_byte(double c)
{
    int v = (int)(c * 256.0);
    if (!(c > 0)) v = 0;
    if (v > 255) v = 255;
    return (unsigned char)v;
}

int main(int argc, char **argv)
{
    if (argc != 3) { fprintf(stderr, "usage: %s scene_description_file output_image\n", argv[0]); return 1; }
    parse(argv[1]);
    int n = res;
    unsigned char *img = malloc((size_t)n * n * 3);
    double *fb = malloc((size_t)n * n * 3 * sizeof *fb);
    if (!img || !fb) die("out of memory", NULL);
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            vec s = v3(-0.5 + (i + 0.5) / n, 0.5 - (j + 0.5) / n, -1);
            vec c = trace(v3(0, 0, 0), vnorm(s), 0, 1e-9);
            double *px = fb + 3 * ((size_t)j * n + i);
            px[0] = c.x; px[1] = c.y; px[2] = c.z;
        }
    }
    /* quantise to 8 bits with Floyd-Steinberg error diffusion */
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) {
                size_t at = 3 * ((size_t)j * n + i) + k;
                double want = fb[at] * 255.0;
                if (want < 0) want = 0;
                if (want > 255) want = 255;
                int q = (int)floor(want + 0.5);
                img[at] = (unsigned char)q;
                double e = want - q;
                if (i + 1 < n) fb[at + 3] += e * 7 / 16 / 255.0;
                if (j + 1 < n) {
                    if (i > 0) fb[at + 3 * n - 3] += e * 3 / 16 / 255.0;
                    fb[at + 3 * n] += e * 5 / 16 / 255.0;
                    if (i + 1 < n) fb[at + 3 * n + 3] += e * 1 / 16 / 255.0;
                }
            }
    FILE *out = fopen(argv[2], "wb");
    if (!out) die("cannot open output file", argv[2]);
    fprintf(out, "P6\n%d %d\n255\n", n, n);
    if (fwrite(img, 1, (size_t)n * n * 3, out) != (size_t)n * n * 3 || fclose(out) != 0) die("cannot write output", argv[2]);
    return 0;
}
