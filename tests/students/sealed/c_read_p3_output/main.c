/* HW4 ray tracer - C version.
 * usage: ./tracer scene_description_file output_image
 *
 * Scene format: "camera N", then "sphere" / "plane" / "light" sections,
 * one attribute per line.  Output is a binary PPM (P6), N x N pixels.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define AMBIENT 0.1       /* k_a */
#define MAX_DEPTH 5       /* max number of mirror bounces */
#define EPS 1e-4          /* offset of secondary ray origins along the normal */
#define T_MIN 1e-6        /* smallest accepted ray parameter */

typedef struct { double x, y, z; } vec;

static vec v3(double x, double y, double z) { vec r = {x, y, z}; return r; }
static vec add(vec a, vec b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec sub(vec a, vec b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec scale(vec a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static vec mul(vec a, vec b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static double dot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec cross(vec a, vec b) {
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double len(vec a) { return sqrt(dot(a, a)); }
static vec norm(vec a) { double l = len(a); return l > 0 ? scale(a, 1.0 / l) : a; }

typedef struct {
    int w, h;
    float *pix; /* rgb, 0..1, row 0 = top of the image */
} texture;

enum { SPHERE, PLANE };

typedef struct {
    int kind;
    vec center;
    double radius;        /* sphere */
    double width, height; /* plane */
    vec normal, up, right;
    vec color;
    double refl;
    texture *tex;
    int has_center, has_dim, has_normal, has_up;
} object;

typedef struct {
    vec pos, color;
    int has_pos;
} light;

static object *objs;
static int nobj, capobj;
static light *lights;
static int nlight, caplight;
static int resolution = -1;

static const char *scene_name;
static int line_no;

static void die(const char *fmt, ...) {
    va_list ap;
    fprintf(stderr, "error: ");
    if (scene_name && line_no > 0) fprintf(stderr, "%s:%d: ", scene_name, line_no);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n");
    exit(1);
}

/* ---------------------------------------------------------------- PPM input */

typedef struct {
    unsigned char *data;
    size_t size, pos;
    const char *name;
} reader;

static void skip_ws_comments(reader *r) {
    while (r->pos < r->size) {
        unsigned char c = r->data[r->pos];
        if (c == '#') {
            while (r->pos < r->size && r->data[r->pos] != '\n' && r->data[r->pos] != '\r') r->pos++;
        } else if (isspace(c)) {
            r->pos++;
        } else {
            break;
        }
    }
}

static long read_uint(reader *r, const char *what) {
    skip_ws_comments(r);
    if (r->pos >= r->size || !isdigit(r->data[r->pos]))
        die("texture %s: bad or missing %s", r->name, what);
    long v = 0;
    while (r->pos < r->size && isdigit(r->data[r->pos])) {
        v = v * 10 + (r->data[r->pos] - '0');
        if (v > 100000000L) die("texture %s: %s too large", r->name, what);
        r->pos++;
    }
    return v;
}

static texture *load_ppm(const char *path, const char *shown) {
    FILE *f = fopen(path, "rb");
    if (!f) die("cannot open texture %s: %s", shown, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    unsigned char *buf = malloc(cap);
    if (!buf) die("out of memory");
    for (;;) {
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap);
            if (!buf) die("out of memory");
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        if (got == 0) break;
        n += got;
    }
    fclose(f);
    reader r = {buf, n, 0, shown};
    if (n < 2 || buf[0] != 'P' || (buf[1] != '3' && buf[1] != '6'))
        die("texture %s is not a P3 or P6 PPM file", shown);
    int binary = buf[1] == '6';
    r.pos = 2;
    long w = read_uint(&r, "width");
    long h = read_uint(&r, "height");
    long maxval = read_uint(&r, "maxval");
    if (w <= 0 || h <= 0 || w * h > 100000000L) die("texture %s: bad size %ldx%ld", shown, w, h);
    if (maxval <= 0 || maxval > 65535) die("texture %s: bad maxval %ld", shown, maxval);
    texture *t = malloc(sizeof *t);
    if (!t) die("out of memory");
    t->w = (int)w;
    t->h = (int)h;
    t->pix = malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
    if (!t->pix) die("out of memory");
    size_t count = (size_t)w * (size_t)h * 3;
    if (binary) {
        /* exactly one whitespace byte after maxval */
        if (r.pos >= n || !isspace(buf[r.pos])) die("texture %s: bad header", shown);
        r.pos++;
        int bps = maxval > 255 ? 2 : 1;
        if (n - r.pos < count * bps) die("texture %s: pixel data is truncated", shown);
        for (size_t i = 0; i < count; i++) {
            long v;
            if (bps == 1) {
                v = buf[r.pos++];
            } else {
                v = (buf[r.pos] << 8) | buf[r.pos + 1];
                r.pos += 2;
            }
            if (v > maxval) die("texture %s: sample larger than maxval", shown);
            t->pix[i] = (float)((double)v / (double)maxval);
        }
    } else {
        for (size_t i = 0; i < count; i++) {
            skip_ws_comments(&r);
            if (r.pos >= n) die("texture %s: pixel data is truncated", shown);
            long v = read_uint(&r, "sample");
            if (v > maxval) die("texture %s: sample larger than maxval", shown);
            t->pix[i] = (float)((double)v / (double)maxval);
        }
    }
    free(buf);
    return t;
}

static vec tex_lookup(const texture *t, double u, double v) {
    /* nearest texel; u to the right, v downwards, both in [0,1] */
    int x = (int)floor(u * t->w);
    int y = (int)floor(v * t->h);
    if (x < 0) x = 0;
    if (x >= t->w) x = t->w - 1;
    if (y < 0) y = 0;
    if (y >= t->h) y = t->h - 1;
    const float *p = t->pix + 3 * ((size_t)y * t->w + x);
    return v3(p[0], p[1], p[2]);
}

/* ---------------------------------------------------------- scene parsing */

static char *next_token(char **s) {
    char *p = *s;
    while (*p && isspace((unsigned char)*p)) p++;
    if (!*p) { *s = p; return NULL; }
    char *start = p;
    while (*p && !isspace((unsigned char)*p)) p++;
    if (*p) *p++ = '\0';
    *s = p;
    return start;
}

static double parse_number(char **s, const char *key) {
    char *tok = next_token(s);
    if (!tok) die("'%s' needs more numbers", key);
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (*end || end == tok || errno == ERANGE || !isfinite(v)) die("'%s': '%s' is not a number", key, tok);
    return v;
}

static vec parse_vec(char **s, const char *key) {
    vec r;
    r.x = parse_number(s, key);
    r.y = parse_number(s, key);
    r.z = parse_number(s, key);
    return r;
}

static void expect_end(char **s, const char *key) {
    char *tok = next_token(s);
    if (tok) die("unexpected '%s' after '%s'", tok, key);
}

static void check_color(vec c, const char *what) {
    if (c.x < 0 || c.y < 0 || c.z < 0) die("%s must not be negative", what);
}

enum { SEC_NONE, SEC_CAMERA, SEC_OBJECT, SEC_LIGHT };

static char scene_dir[4096];

static void finish_object(object *o) {
    const char *name = o->kind == SPHERE ? "sphere" : "plane";
    if (!o->has_center) die("%s without center", name);
    if (!o->has_dim) die("%s without dimension", name);
    if (o->kind == PLANE) {
        if (!o->has_normal) die("plane without normal");
        if (!o->has_up) die("plane without headup");
        double nl = len(o->normal);
        if (nl == 0) die("plane normal is zero");
        o->normal = scale(o->normal, 1.0 / nl);
        /* make headup perpendicular to the normal */
        vec up = sub(o->up, scale(o->normal, dot(o->up, o->normal)));
        if (len(up) < 1e-9 * (len(o->up) + 1e-300)) die("plane headup is parallel to its normal");
        o->up = norm(up);
        o->right = cross(o->up, o->normal);
    }
}

static void finish_section(int sec) {
    int save = line_no;
    line_no = 0;
    if (sec == SEC_OBJECT) finish_object(&objs[nobj - 1]);
    if (sec == SEC_LIGHT && !lights[nlight - 1].has_pos) die("light without location");
    line_no = save;
}

static void parse_scene(const char *path) {
    FILE *f = fopen(path, "r");
    if (!f) die("cannot open scene file %s: %s", path, strerror(errno));
    scene_name = path;
    /* folder of the scene file, for texture paths */
    strncpy(scene_dir, path, sizeof scene_dir - 1);
    char *slash = strrchr(scene_dir, '/');
    if (slash) slash[1] = '\0';
    else scene_dir[0] = '\0';

    int sec = SEC_NONE;
    char line[8192];
    while (fgets(line, sizeof line, f)) {
        line_no++;
        size_t l = strlen(line);
        if (l == sizeof line - 1 && line[l - 1] != '\n' && !feof(f)) die("line too long");
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        char *s = line;
        char *key = next_token(&s);
        if (!key) continue;
        for (char *p = key; *p; p++) *p = (char)tolower((unsigned char)*p);

        if (!strcmp(key, "camera")) {
            if (resolution > 0) die("more than one camera");
            finish_section(sec);
            char *tok = next_token(&s);
            if (!tok) die("camera needs a resolution");
            char *end;
            errno = 0;
            long n = strtol(tok, &end, 10);
            if (*end || errno || n <= 0 || n > 20000) die("bad camera resolution '%s'", tok);
            expect_end(&s, key);
            resolution = (int)n;
            sec = SEC_CAMERA;
        } else if (!strcmp(key, "sphere") || !strcmp(key, "plane")) {
            finish_section(sec);
            expect_end(&s, key);
            if (nobj == capobj) {
                capobj = capobj ? capobj * 2 : 8;
                objs = realloc(objs, sizeof *objs * capobj);
                if (!objs) die("out of memory");
            }
            object *o = &objs[nobj++];
            memset(o, 0, sizeof *o);
            o->kind = key[0] == 's' ? SPHERE : PLANE;
            o->color = v3(1, 1, 1);
            o->refl = 0;
            sec = SEC_OBJECT;
        } else if (!strcmp(key, "light")) {
            finish_section(sec);
            expect_end(&s, key);
            if (nlight == caplight) {
                caplight = caplight ? caplight * 2 : 8;
                lights = realloc(lights, sizeof *lights * caplight);
                if (!lights) die("out of memory");
            }
            light *li = &lights[nlight++];
            memset(li, 0, sizeof *li);
            li->color = v3(1, 1, 1);
            sec = SEC_LIGHT;
        } else if (sec == SEC_OBJECT) {
            object *o = &objs[nobj - 1];
            if (!strcmp(key, "center")) {
                o->center = parse_vec(&s, key);
                o->has_center = 1;
            } else if (!strcmp(key, "dimension")) {
                if (o->kind == SPHERE) {
                    o->radius = parse_number(&s, key);
                    if (o->radius <= 0) die("sphere dimension must be positive");
                } else {
                    o->width = parse_number(&s, key);
                    o->height = parse_number(&s, key);
                    if (o->width <= 0 || o->height <= 0) die("plane dimensions must be positive");
                }
                o->has_dim = 1;
            } else if (!strcmp(key, "color") || !strcmp(key, "colour")) {
                o->color = parse_vec(&s, key);
                check_color(o->color, "object color");
            } else if (!strcmp(key, "reflectivity")) {
                o->refl = parse_number(&s, key);
                if (o->refl < 0) die("reflectivity must not be negative");
            } else if (!strcmp(key, "texture")) {
                char *name = next_token(&s);
                if (!name) die("texture needs a file name");
                expect_end(&s, key);
                char full[8192];
                if (name[0] == '/') snprintf(full, sizeof full, "%s", name);
                else snprintf(full, sizeof full, "%s%s", scene_dir, name);
                o->tex = load_ppm(full, name);
                continue; /* already checked the end of the line */
            } else if (o->kind == PLANE && !strcmp(key, "normal")) {
                o->normal = parse_vec(&s, key);
                o->has_normal = 1;
            } else if (o->kind == PLANE && !strcmp(key, "headup")) {
                o->up = parse_vec(&s, key);
                o->has_up = 1;
            } else {
                die("unknown %s attribute '%s'", o->kind == SPHERE ? "sphere" : "plane", key);
            }
            expect_end(&s, key);
        } else if (sec == SEC_LIGHT) {
            light *li = &lights[nlight - 1];
            if (!strcmp(key, "location")) {
                li->pos = parse_vec(&s, key);
                li->has_pos = 1;
            } else if (!strcmp(key, "color") || !strcmp(key, "colour")) {
                li->color = parse_vec(&s, key);
                check_color(li->color, "light color");
            } else {
                die("unknown light attribute '%s'", key);
            }
            expect_end(&s, key);
        } else {
            die("unexpected '%s'", key);
        }
    }
    if (ferror(f)) die("error reading scene file");
    fclose(f);
    finish_section(sec);
    line_no = 0;
    if (resolution <= 0) die("scene has no camera");
}

/* ------------------------------------------------------------- ray tracing */

/* distance along the ray to the object, or -1 */
static double intersect(const object *o, vec orig, vec dir) {
    if (o->kind == SPHERE) {
        vec oc = sub(orig, o->center);
        double a = dot(dir, dir);
        double b = 2 * dot(dir, oc);
        double c = dot(oc, oc) - o->radius * o->radius;
        double disc = b * b - 4 * a * c;
        if (disc < 0) return -1;
        double d = sqrt(disc);
        double t1 = (-b - d) / (2 * a);
        double t2 = (-b + d) / (2 * a);
        if (t1 > T_MIN) return t1;
        if (t2 > T_MIN) return t2;
        return -1;
    } else {
        double denom = dot(o->normal, dir);
        if (fabs(denom) < 1e-12) return -1;
        double t = dot(o->normal, sub(o->center, orig)) / denom;
        if (t <= T_MIN) return -1;
        vec q = sub(add(orig, scale(dir, t)), o->center);
        if (fabs(dot(q, o->right)) > o->width / 2) return -1;
        if (fabs(dot(q, o->up)) > o->height / 2) return -1;
        return t;
    }
}

static int closest(vec orig, vec dir, double *tbest) {
    int best = -1;
    *tbest = INFINITY;
    for (int i = 0; i < nobj; i++) {
        double t = intersect(&objs[i], orig, dir);
        if (t > 0 && t < *tbest) {
            *tbest = t;
            best = i;
        }
    }
    return best;
}

static int in_shadow(vec orig, vec dir, double maxdist) {
    for (int i = 0; i < nobj; i++) {
        double t = intersect(&objs[i], orig, dir);
        if (t > 0 && t < maxdist) return 1;
    }
    return 0;
}

static vec surface_color(const object *o, vec p) {
    if (!o->tex) return o->color;
    double u, v;
    if (o->kind == SPHERE) {
        vec n = scale(sub(p, o->center), 1.0 / o->radius);
        double ny = n.y > 1 ? 1 : (n.y < -1 ? -1 : n.y);
        u = 0.5 + atan2(n.x, n.z) / (2 * M_PI);
        v = acos(ny) / M_PI;
    } else {
        vec q = sub(p, o->center);
        u = dot(q, o->right) / o->width + 0.5;
        v = 0.5 - dot(q, o->up) / o->height;
    }
    return tex_lookup(o->tex, u, v);
}

static vec trace(vec orig, vec dir, int depth) {
    double t;
    int hit = closest(orig, dir, &t);
    if (hit < 0) return v3(0, 0, 0); /* background */
    const object *o = &objs[hit];
    vec p = add(orig, scale(dir, t));
    vec n = o->kind == SPHERE ? scale(sub(p, o->center), 1.0 / o->radius) : o->normal;
    if (dot(n, dir) > 0) n = scale(n, -1); /* face the incoming ray */
    vec base = surface_color(o, p);
    vec col = scale(base, AMBIENT);
    vec p_off = add(p, scale(n, EPS));
    for (int i = 0; i < nlight; i++) {
        vec L = sub(lights[i].pos, p);
        double dist = len(L);
        if (dist == 0) continue;
        L = scale(L, 1.0 / dist);
        double ndl = dot(n, L);
        if (ndl <= 0) continue;
        if (in_shadow(p_off, L, dist)) continue;
        col = add(col, scale(mul(base, lights[i].color), ndl));
    }
    if (o->refl > 0 && depth < MAX_DEPTH) {
        vec r = norm(sub(dir, scale(n, 2 * dot(dir, n))));
        vec rc = trace(p_off, r, depth + 1);
        col = add(col, scale(rc, o->refl));
    }
    return col;
}

static unsigned char to_byte(double c) {
    if (!(c > 0)) c = 0;
    if (c > 1) c = 1;
    return (unsigned char)(c * 255 + 0.5);
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: %s scene_description_file output_image\n", argv[0]);
        return 1;
    }
    parse_scene(argv[1]);
    scene_name = NULL;
    int n = resolution;
    unsigned char *img = malloc((size_t)n * n * 3);
    if (!img) die("out of memory");
    vec eye = v3(0, 0, 0);
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            vec s = v3(-0.5 + (i + 0.5) / n, 0.5 - (j + 0.5) / n, -1);
            vec c = trace(eye, norm(s), 0);
            unsigned char *px = img + 3 * ((size_t)j * n + i);
            px[0] = to_byte(c.x);
            px[1] = to_byte(c.y);
            px[2] = to_byte(c.z);
        }
    }
    FILE *out = fopen(argv[2], "wb");
    if (!out) die("cannot write %s: %s", argv[2], strerror(errno));
    fprintf(out, "P3\n%d %d\n255\n", n, n);
    size_t want = (size_t)n * n * 3;
    int bad = 0;
    for (size_t k = 0; k < want; k++)
        if (fprintf(out, "%d%c", img[k], (k % 12 == 11 || k == want - 1) ? '\n' : ' ') < 0) bad = 1;
    if (bad || fclose(out) != 0) {
        remove(argv[2]);
        die("error writing %s", argv[2]);
    }
    free(img);
    return 0;
}
