/* HW4 ray tracer.
 * usage: ./tracer scene.txt out.ppm
 * Reads the scene file (camera / sphere / plane / light sections, one
 * attribute per line) and writes a binary PPM (P6).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

#define MAXOBJ 256
#define MAXLIGHT 64
#define MAXDEPTH 5
#define KA 0.1

typedef struct { double x, y, z; } vec;

static vec v3(double x, double y, double z) { vec r = {x, y, z}; return r; }
static vec add(vec a, vec b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec sub(vec a, vec b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec mul(vec a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static vec vmul(vec a, vec b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static double dot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec cross(vec a, vec b) {
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double len(vec a) { return sqrt(dot(a, a)); }
static vec norm(vec a) { double l = len(a); return l > 0 ? mul(a, 1.0 / l) : a; }

typedef struct {
    int w, h;
    unsigned char *rgb;
} image;

enum { SPHERE, PLANE };

typedef struct {
    int type;
    double dim[2];          /* sphere: radius; plane: width height */
    vec center, color, normal, headup;
    double refl;
    char texname[512];
    image *tex;
    vec right, up;          /* plane axes, computed after parsing */
} object;

typedef struct { vec pos, color; } light;

static int res = 0;
static object objs[MAXOBJ];
static int nobj = 0;
static light lights[MAXLIGHT];
static int nlight = 0;

/* ---------- PPM texture loading (P3 and P6) ---------- */

static int ppm_token(FILE *f, char *buf, int n) {
    int c, i = 0;
    for (;;) {
        c = fgetc(f);
        if (c == EOF) return 0;
        if (c == '#') { while (c != '\n' && c != EOF) c = fgetc(f); continue; }
        if (!(c == ' ' || c == '\t' || c == '\n' || c == '\r')) break;
    }
    while (c != EOF && !(c == ' ' || c == '\t' || c == '\n' || c == '\r') && i < n - 1) {
        buf[i++] = (char)c;
        c = fgetc(f);
    }
    buf[i] = 0;
    return 1;
}

static image *load_ppm(const char *path) {
    FILE *f = fopen(path, "rb");
    char tok[64];
    if (!f) { fprintf(stderr, "cannot open texture %s\n", path); return NULL; }
    ppm_token(f, tok, sizeof tok);
    int binary = strcmp(tok, "P6") == 0;
    if (!binary && strcmp(tok, "P3") != 0) { fprintf(stderr, "%s: not a PPM\n", path); fclose(f); return NULL; }
    ppm_token(f, tok, sizeof tok); int w = atoi(tok);
    ppm_token(f, tok, sizeof tok); int h = atoi(tok);
    ppm_token(f, tok, sizeof tok); int maxv = atoi(tok);
    if (w <= 0 || h <= 0 || maxv <= 0) { fclose(f); return NULL; }
    image *im = malloc(sizeof *im);
    im->w = w; im->h = h;
    im->rgb = calloc((size_t)w * h * 3, 1);
    for (long i = 0; i < (long)w * h * 3; i++) {
        int v;
        if (binary) {
            if (maxv < 256) v = fgetc(f);
            else { int hi = fgetc(f); v = hi * 256 + fgetc(f); }
        } else {
            if (!ppm_token(f, tok, sizeof tok)) break;
            v = atoi(tok);
        }
        if (v < 0) break;
        im->rgb[i] = (unsigned char)(v * 255 / maxv);
    }
    fclose(f);
    return im;
}

static vec texel(image *im, double s, double t) {
    /* s, t in [0,1], t = 0 is the top row of the image */
    int x = (int)(s * im->w), y = (int)(t * im->h);
    if (x < 0) x = 0;
    if (x >= im->w) x = im->w - 1;
    if (y < 0) y = 0;
    if (y >= im->h) y = im->h - 1;
    unsigned char *p = im->rgb + 3 * ((size_t)y * im->w + x);
    return v3(p[0] / 255.0, p[1] / 255.0, p[2] / 255.0);
}

/* ---------- scene parsing ---------- */

static void parse_scene(const char *path) {
    FILE *f = fopen(path, "r");
    if (!f) { perror(path); exit(1); }
    char line[1024], key[64];
    int cur = 0; /* 0 none, 1 object, 2 light */
    while (fgets(line, sizeof line, f)) {
        char *hash = strchr(line, '#');
        if (hash) *hash = 0;
        if (sscanf(line, "%63s", key) != 1) continue;
        char *rest = strstr(line, key) + strlen(key);
        if (!strcmp(key, "camera")) {
            res = atoi(rest);
            cur = 0;
        } else if (!strcmp(key, "sphere") || !strcmp(key, "plane")) {
            object *o = &objs[nobj++];
            memset(o, 0, sizeof *o);
            o->type = key[0] == 's' ? SPHERE : PLANE;
            o->color = v3(1, 1, 1);
            cur = 1;
        } else if (!strcmp(key, "light")) {
            light *l = &lights[nlight++];
            l->pos = v3(0, 0, 0);
            l->color = v3(1, 1, 1);
            cur = 2;
        } else if (cur == 1) {
            object *o = &objs[nobj - 1];
            if (!strcmp(key, "dimension")) sscanf(rest, "%lf %lf", &o->dim[0], &o->dim[1]);
            else if (!strcmp(key, "center")) sscanf(rest, "%lf %lf %lf", &o->center.x, &o->center.y, &o->center.z);
            else if (!strcmp(key, "color")) sscanf(rest, "%lf %lf %lf", &o->color.x, &o->color.y, &o->color.z);
            else if (!strcmp(key, "normal")) sscanf(rest, "%lf %lf %lf", &o->normal.x, &o->normal.y, &o->normal.z);
            else if (!strcmp(key, "headup")) sscanf(rest, "%lf %lf %lf", &o->headup.x, &o->headup.y, &o->headup.z);
            else if (!strcmp(key, "reflectivity")) sscanf(rest, "%lf", &o->refl);
            else if (!strcmp(key, "texture")) sscanf(rest, "%511s", o->texname);
            else fprintf(stderr, "unknown attribute %s\n", key);
        } else if (cur == 2) {
            light *l = &lights[nlight - 1];
            if (!strcmp(key, "location")) sscanf(rest, "%lf %lf %lf", &l->pos.x, &l->pos.y, &l->pos.z);
            else if (!strcmp(key, "color")) sscanf(rest, "%lf %lf %lf", &l->color.x, &l->color.y, &l->color.z);
            else fprintf(stderr, "unknown attribute %s\n", key);
        } else {
            fprintf(stderr, "unexpected %s\n", key);
        }
    }
    fclose(f);

    /* textures are relative to the scene file's folder */
    char dir[1024] = "";
    const char *slash = strrchr(path, '/');
    if (slash) { memcpy(dir, path, slash - path + 1); dir[slash - path + 1] = 0; }
    for (int i = 0; i < nobj; i++) {
        object *o = &objs[i];
        if (o->texname[0]) {
            char full[2048];
            if (o->texname[0] == '/') snprintf(full, sizeof full, "%s", o->texname);
            else snprintf(full, sizeof full, "%s%s", dir, o->texname);
            o->tex = load_ppm(full);
        }
        if (o->type == PLANE) {
            o->normal = norm(o->normal);
            /* make headup perpendicular to the normal */
            vec up = sub(o->headup, mul(o->normal, dot(o->headup, o->normal)));
            o->up = norm(up);
            o->right = cross(o->up, o->normal);
        }
    }
}

/* ---------- intersection ---------- */

/* d must be normalised (so a = 1 in the quadratic) */
static double hit_sphere(object *o, vec e, vec d, double tmin) {
    vec ec = sub(e, o->center);
    double b = dot(d, ec);
    double c = dot(ec, ec) - o->dim[0] * o->dim[0];
    double disc = b * b - c;
    if (disc < 0) return -1;
    double sq = sqrt(disc);
    double t = -b - sq;
    if (t > tmin) return t;
    t = -b + sq;
    if (t > tmin) return t;
    return -1;
}

static double hit_plane(object *o, vec e, vec d, double tmin) {
    double dn = dot(d, o->normal);
    if (fabs(dn) < 1e-12) return -1;
    double dd = -dot(o->normal, o->center);
    double t = -(dot(o->normal, e) + dd) / dn;
    if (t <= tmin) return -1;
    vec p = add(e, mul(d, t));
    vec q = sub(p, o->center);
    if (fabs(dot(q, o->right)) > o->dim[0] / 2) return -1;
    if (fabs(dot(q, o->up)) > o->dim[1] / 2) return -1;
    return t;
}

static double intersect(object *o, vec e, vec d, double tmin) {
    return o->type == SPHERE ? hit_sphere(o, e, d, tmin) : hit_plane(o, e, d, tmin);
}

static int closest(vec e, vec d, double tmin, double *tbest) {
    int best = -1;
    *tbest = 1e300;
    for (int i = 0; i < nobj; i++) {
        double t = intersect(&objs[i], e, d, tmin);
        if (t > 0 && t < *tbest) { *tbest = t; best = i; }
    }
    return best;
}

/* epsilon relative to how far from the origin we are */
static double eps_at(vec p) { return 1e-7 * (1.0 + len(p)); }

static vec object_color(object *o, vec p) {
    if (!o->tex) return o->color;
    if (o->type == PLANE) {
        vec q = sub(p, o->center);
        double s = dot(q, o->right) / o->dim[0] + 0.5;
        double t = 0.5 - dot(q, o->up) / o->dim[1];
        return texel(o->tex, s, t);
    } else {
        vec q = mul(sub(p, o->center), 1.0 / o->dim[0]);
        double phi = atan2(q.z, q.x);
        double y = q.y > 1 ? 1 : (q.y < -1 ? -1 : q.y);
        double theta = acos(y);
        return texel(o->tex, (phi + M_PI) / (2 * M_PI), theta / M_PI);
    }
}

static int in_shadow(vec p, light *l) {
    vec tol = sub(l->pos, p);
    double dist = len(tol);
    vec d = mul(tol, 1.0 / dist);
    double eps = eps_at(p);
    for (int i = 0; i < nobj; i++) {
        double t = intersect(&objs[i], p, d, eps);
        if (t > 0 && t < dist - eps) return 1;
    }
    return 0;
}

static vec trace(vec e, vec d, int depth) {
    double t;
    int i = closest(e, d, eps_at(e), &t);
    if (i < 0) return v3(0, 0, 0);
    object *o = &objs[i];
    vec p = add(e, mul(d, t));
    vec n;
    if (o->type == SPHERE) n = mul(sub(p, o->center), 1.0 / o->dim[0]);
    else n = o->normal;
    n = norm(n);
    if (dot(n, d) > 0) n = mul(n, -1); /* face the viewer (planes are two-sided, inside of spheres) */

    vec base = object_color(o, p);
    vec col = mul(base, KA);
    for (int k = 0; k < nlight; k++) {
        light *l = &lights[k];
        vec L = sub(l->pos, p);
        double dist = len(L);
        if (dist == 0) continue;
        L = mul(L, 1.0 / dist);
        double ndl = dot(n, L);
        if (ndl <= 0) continue;
        if (in_shadow(p, l)) continue;
        col = add(col, mul(vmul(base, l->color), ndl));
    }
    if (o->refl > 0 && depth < MAXDEPTH) {
        vec v = mul(d, -1);
        vec r = sub(mul(n, 2 * dot(n, v)), v);
        vec rc = trace(p, r, depth + 1);
        col = add(col, mul(rc, o->refl));
    }
    return col;
}

static unsigned char to_byte(double c) {
    if (c < 0) c = 0;
    if (c > 1) c = 1;
    return (unsigned char)(pow(c, 1 / 2.2) * 255); /* gamma 2.2 for the screen */
}

int main(int argc, char **argv) {
    if (argc < 3) { fprintf(stderr, "usage: %s scene out.ppm\n", argv[0]); return 1; }
    parse_scene(argv[1]);
    if (res <= 0) { fprintf(stderr, "no camera\n"); return 1; }
    int n = res;
    unsigned char *img = malloc((size_t)n * n * 3);
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            /* image plane z = -1, 1x1, centre of the pixel */
            double x = -0.5 + (i + 0.5) / n;
            double y = 0.5 - (j + 0.5) / n;
            vec d = norm(v3(x, y, -1));
            vec c = trace(v3(0, 0, 0), d, 0);
            unsigned char *px = img + 3 * ((size_t)j * n + i);
            px[0] = to_byte(c.x);
            px[1] = to_byte(c.y);
            px[2] = to_byte(c.z);
        }
    }
    FILE *f = fopen(argv[2], "wb");
    if (!f) { perror(argv[2]); return 1; }
    fprintf(f, "P6\n%d %d\n255\n", n, n);
    fwrite(img, 1, (size_t)n * n * 3, f);
    fclose(f);
    return 0;
}
