/* HW4 ray tracer - C version
 * usage: ./tracer scene_file output_image
 * writes a binary PPM (P6) of camera x camera pixels.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

#define MAX_OBJ 256
#define MAX_LIGHT 64
#define MAX_DEPTH 5
#define KA 0.1
#define T_MIN 1e-6
#define OFFSET 1e-4

typedef struct { double x, y, z; } vec;

static vec v3(double x, double y, double z) { vec r = {x, y, z}; return r; }
static vec add(vec a, vec b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec sub(vec a, vec b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec mul(vec a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static vec had(vec a, vec b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static double dot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec cross(vec a, vec b) {
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double len(vec a) { return sqrt(dot(a, a)); }
static vec norm(vec a) { double l = len(a); return l > 0 ? mul(a, 1.0 / l) : a; }

typedef struct { int w, h; unsigned char *px; } image_t;

enum { SPHERE, PLANE };

typedef struct {
    int kind;
    vec center;
    double dim[2];
    vec color;
    double refl;
    vec normal, headup;
    vec up, right;          /* plane frame */
    image_t *tex;
} object_t;

typedef struct { vec pos, color; } light_t;

typedef struct {
    double t;
    int obj;
    vec p, n;
} hit_t;

static object_t objs[MAX_OBJ];
static int nobj = 0;
static light_t lights[MAX_LIGHT];
static int nlight = 0;
static int res = 0;

static void die(const char *msg, const char *arg) {
    fprintf(stderr, "tracer: %s%s%s\n", msg, arg ? ": " : "", arg ? arg : "");
    exit(1);
}

/* ---------- PPM texture loading ---------- */

static int ppm_token(FILE *f, char *buf, int n) {
    int c, i = 0;
    for (;;) {
        c = fgetc(f);
        if (c == EOF) return 0;
        if (c == '#') { while (c != '\n' && c != EOF) c = fgetc(f); continue; }
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') continue;
        break;
    }
    while (c != EOF && c != ' ' && c != '\t' && c != '\n' && c != '\r' && i < n - 1) {
        buf[i++] = (char)c;
        c = fgetc(f);
    }
    buf[i] = 0;
    return 1;
}

static image_t *load_ppm(const char *path) {
    FILE *f = fopen(path, "rb");
    char tok[64];
    int w, h, maxv, i;
    image_t *img;
    if (!f) die("cannot open texture", path);
    if (!ppm_token(f, tok, sizeof tok) || strcmp(tok, "P6") != 0) die("texture is not a P6 PPM", path);
    if (!ppm_token(f, tok, sizeof tok)) die("bad texture header", path);
    w = atoi(tok);
    if (!ppm_token(f, tok, sizeof tok)) die("bad texture header", path);
    h = atoi(tok);
    if (!ppm_token(f, tok, sizeof tok)) die("bad texture header", path);
    maxv = atoi(tok);
    if (w <= 0 || h <= 0 || maxv <= 0 || maxv > 255) die("unsupported texture size/maxval", path);
    img = malloc(sizeof *img);
    img->w = w; img->h = h;
    img->px = malloc((size_t)w * h * 3);
    if (fread(img->px, 3, (size_t)w * h, f) != (size_t)w * h) die("texture data truncated", path);
    if (maxv != 255)
        for (i = 0; i < w * h * 3; i++) img->px[i] = (unsigned char)(img->px[i] * 255 / maxv);
    fclose(f);
    return img;
}

/* nearest texel, u,v in [0,1], v = 0 is the top row */
static vec texel(image_t *img, double u, double v) {
    int x = (int)(u * img->w), y = (int)(v * img->h);
    unsigned char *p;
    if (x < 0) x = 0;
    if (x >= img->w) x = img->w - 1;
    if (y < 0) y = 0;
    if (y >= img->h) y = img->h - 1;
    p = img->px + 3 * ((size_t)y * img->w + x);
    return v3(p[0] / 255.0, p[1] / 255.0, p[2] / 255.0);
}

/* ---------- scene parsing ---------- */

static char **toks;
static int ntok, tpos;

static const char *next_tok(void) { return tpos < ntok ? toks[tpos++] : NULL; }

static double num(const char *what) {
    const char *t = next_tok();
    char *end;
    double d;
    if (!t) die("missing number after", what);
    d = strtod(t, &end);
    if (end == t || *end != 0) die("expected a number after", what);
    return d;
}

static vec num3(const char *what) {
    double x = num(what), y = num(what), z = num(what);
    return v3(x, y, z);
}

static void setup_plane(object_t *o) {
    vec n, up;
    o->normal = norm(o->normal);
    n = o->normal;
    up = sub(o->headup, mul(n, dot(o->headup, n)));
    if (len(up) < 1e-9) {
        /* headup parallel to the normal: use the world axis least aligned with it */
        vec a;
        if (fabs(n.x) <= fabs(n.y) && fabs(n.x) <= fabs(n.z)) a = v3(1, 0, 0);
        else if (fabs(n.y) <= fabs(n.z)) a = v3(0, 1, 0);
        else a = v3(0, 0, 1);
        up = sub(a, mul(n, dot(a, n)));
    }
    o->up = norm(up);
    o->right = cross(o->up, n);
}

static void parse_scene(const char *path) {
    FILE *f = fopen(path, "rb");
    char *buf, *dir, *s;
    long sz, i;
    object_t *cur = NULL;
    light_t *curl = NULL;
    int mode = 0; /* 0 none, 1 object, 2 light */
    const char *t;

    if (!f) die("cannot open scene file", path);
    fseek(f, 0, SEEK_END);
    sz = ftell(f);
    fseek(f, 0, SEEK_SET);
    buf = malloc(sz + 1);
    if (fread(buf, 1, sz, f) != (size_t)sz) die("cannot read scene file", path);
    buf[sz] = 0;
    fclose(f);
    /* stray non-ASCII bytes (e.g. pasted line separators) count as white space */
    for (i = 0; i < sz; i++)
        if ((unsigned char)buf[i] >= 0x80 || buf[i] == 0) buf[i] = ' ';

    toks = malloc(sizeof(char *) * (sz / 2 + 2));
    ntok = 0;
    for (s = strtok(buf, " \t\r\n\v\f"); s; s = strtok(NULL, " \t\r\n\v\f")) toks[ntok++] = s;
    tpos = 0;

    dir = malloc(strlen(path) + 2);
    strcpy(dir, path);
    s = strrchr(dir, '/');
    if (s) s[1] = 0; else dir[0] = 0;

    while ((t = next_tok()) != NULL) {
        if (!strcmp(t, "camera")) {
            double r = num("camera");
            if (r < 1 || r > 20000 || r != floor(r)) die("bad camera resolution", NULL);
            res = (int)r;
        } else if (!strcmp(t, "sphere") || !strcmp(t, "plane")) {
            if (nobj >= MAX_OBJ) die("too many objects", NULL);
            cur = &objs[nobj++];
            memset(cur, 0, sizeof *cur);
            cur->kind = !strcmp(t, "sphere") ? SPHERE : PLANE;
            cur->color = v3(1, 1, 1);
            cur->dim[0] = cur->dim[1] = 1;
            cur->normal = v3(0, 0, 1);
            cur->headup = v3(0, 1, 0);
            mode = 1;
        } else if (!strcmp(t, "light")) {
            if (nlight >= MAX_LIGHT) die("too many lights", NULL);
            curl = &lights[nlight++];
            curl->pos = v3(0, 0, 0);
            curl->color = v3(1, 1, 1);
            mode = 2;
        } else if (!strcmp(t, "color")) {
            vec c = num3(t);
            if (mode == 1) cur->color = c;
            else if (mode == 2) curl->color = c;
            else die("color outside of an object or light", NULL);
        } else if (!strcmp(t, "location")) {
            if (mode != 2) die("location outside of a light", NULL);
            curl->pos = num3(t);
        } else if (mode == 1 && !strcmp(t, "dimension")) {
            cur->dim[0] = num(t);
            if (cur->kind == PLANE) cur->dim[1] = num(t);
            if (cur->dim[0] <= 0 || (cur->kind == PLANE && cur->dim[1] <= 0))
                die("dimension must be positive", NULL);
        } else if (mode == 1 && !strcmp(t, "center")) {
            cur->center = num3(t);
        } else if (mode == 1 && !strcmp(t, "reflectivity")) {
            cur->refl = num(t);
            if (cur->refl < 0 || cur->refl > 1) die("reflectivity must be in [0,1]", NULL);
        } else if (mode == 1 && !strcmp(t, "normal")) {
            cur->normal = num3(t);
            if (len(cur->normal) == 0) die("plane normal is zero", NULL);
        } else if (mode == 1 && !strcmp(t, "headup")) {
            cur->headup = num3(t);
        } else if (mode == 1 && !strcmp(t, "texture")) {
            const char *name = next_tok();
            char *full;
            if (!name) die("missing texture file name", NULL);
            full = malloc(strlen(dir) + strlen(name) + 1);
            if (name[0] == '/') strcpy(full, name);
            else { strcpy(full, dir); strcat(full, name); }
            cur->tex = load_ppm(full);
            free(full);
        } else {
            die("unknown or misplaced keyword", t);
        }
    }
    if (res <= 0) die("scene has no camera line", NULL);
    for (i = 0; i < nobj; i++)
        if (objs[i].kind == PLANE) setup_plane(&objs[i]);
}

/* ---------- intersection ---------- */

static double hit_sphere(object_t *o, vec orig, vec d) {
    vec oc = sub(orig, o->center);
    double b = 2 * dot(d, oc);
    double c = dot(oc, oc) - o->dim[0] * o->dim[0];
    double disc = b * b - 4 * c, sq, t;
    if (disc < 0) return -1;
    sq = sqrt(disc);
    t = (-b - sq) / 2;
    if (t > T_MIN) return t;
    t = (-b + sq) / 2;
    if (t > T_MIN) return t;
    return -1;
}

static double hit_plane(object_t *o, vec orig, vec d) {
    double den = dot(o->normal, d), t;
    vec q;
    if (fabs(den) < 1e-12) return -1;
    t = dot(o->normal, sub(o->center, orig)) / den;
    if (t <= T_MIN) return -1;
    q = sub(add(orig, mul(d, t)), o->center);
    if (fabs(dot(q, o->right)) > o->dim[0] / 2) return -1;
    if (fabs(dot(q, o->up)) > o->dim[1] / 2) return -1;
    return t;
}

static double hit_obj(object_t *o, vec orig, vec d) {
    return o->kind == SPHERE ? hit_sphere(o, orig, d) : hit_plane(o, orig, d);
}

static int closest(vec orig, vec d, hit_t *h) {
    int i;
    h->t = 1e30;
    h->obj = -1;
    for (i = 0; i < nobj; i++) {
        double t = hit_obj(&objs[i], orig, d);
        if (t > 0 && t < h->t) { h->t = t; h->obj = i; }
    }
    if (h->obj < 0) return 0;
    h->p = add(orig, mul(d, h->t));
    if (objs[h->obj].kind == SPHERE) h->n = norm(sub(h->p, objs[h->obj].center));
    else h->n = objs[h->obj].normal;
    return 1;
}

/* is anything between p and the light (distance dist along unit dir L)? */
static int occluded(vec p, vec L, double dist) {
    int i;
    for (i = 0; i < nobj; i++) {
        double t = hit_obj(&objs[i], p, L);
        if (t > 0 && t < dist) return 1;
    }
    return 0;
}

static vec surface_color(object_t *o, vec p) {
    vec q;
    double u, v;
    if (!o->tex) return o->color;
    if (o->kind == SPHERE) {
        q = norm(sub(p, o->center));
        u = 0.5 + atan2(q.z, q.x) / (2 * M_PI);
        v = acos(q.y < -1 ? -1 : q.y > 1 ? 1 : q.y) / M_PI;
    } else {
        q = sub(p, o->center);
        u = dot(q, o->right) / o->dim[0] + 0.5;
        v = 0.5 - dot(q, o->up) / o->dim[1];
    }
    return texel(o->tex, u, v);
}

/* ---------- shading ---------- */

static vec trace(vec orig, vec d, int depth) {
    hit_t h;
    object_t *o;
    vec n, col, local, sp;
    int i;

    if (!closest(orig, d, &h)) return v3(0, 0, 0);
    o = &objs[h.obj];
    n = h.n;
    if (dot(n, d) > 0) n = mul(n, -1); /* two-sided: face the incoming ray */
    col = surface_color(o, h.p);
    sp = add(h.p, mul(n, OFFSET));

    local = mul(col, KA);
    for (i = 0; i < nlight; i++) {
        vec L = sub(lights[i].pos, h.p);
        double dist = len(L), ndl;
        L = mul(L, 1.0 / dist);
        ndl = dot(n, L);
        if (ndl <= 0) continue;
        if (occluded(sp, L, dist)) continue;
        local = add(local, mul(had(col, lights[i].color), ndl));
    }

    if (o->refl > 0 && depth < MAX_DEPTH) {
        vec r = sub(d, mul(n, 2 * dot(d, n)));
        vec rc = trace(sp, norm(r), depth + 1);
        local = add(local, mul(rc, o->refl));
    }
    return local;
}

static unsigned char to_byte(double c) {
    if (c < 0) c = 0;
    if (c > 1) c = 1;
    return (unsigned char)(c * 255 + 0.5);
}

int main(int argc, char **argv) {
    FILE *out;
    unsigned char *img;
    int i, j;

    if (argc != 3) {
        fprintf(stderr, "usage: %s scene_file output_image\n", argv[0]);
        return 1;
    }
    parse_scene(argv[1]);
    img = malloc((size_t)res * res * 3);
    for (j = 0; j < res; j++) {
        for (i = 0; i < res; i++) {
            vec s = v3(-0.5 + (i + 0.5) / res, 0.5 - (j + 0.5) / res, -1);
            vec c = trace(v3(0, 0, 0), norm(s), 0);
            /* tone map on luminance: L' = L / (1 + L), hue kept */
            double lum = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
            if (lum > 0) c = mul(c, 1.0 / (1.0 + lum));
            unsigned char *p = img + 3 * ((size_t)j * res + i);
            p[0] = to_byte(c.x);
            p[1] = to_byte(c.y);
            p[2] = to_byte(c.z);
        }
    }
    out = fopen(argv[2], "wb");
    if (!out) die("cannot open output file", argv[2]);
    fprintf(out, "P6\n%d %d\n255\n", res, res);
    if (fwrite(img, 3, (size_t)res * res, out) != (size_t)res * res) die("write failed", argv[2]);
    fclose(out);
    return 0;
}
