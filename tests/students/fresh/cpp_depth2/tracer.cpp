// HW4 ray tracer (C++).
// usage: ./tracer scene_description_file output_image
//
// Design choices (the handout leaves these to us):
//  - sphere "dimension" is the radius; plane "dimension w h" is the full
//    width (along headup x normal) and full height (along headup)
//  - one ray through the centre of each pixel, image plane z = -1, 1x1
//  - Phong-style local model without a highlight:
//      ambient 0.1 * colour + sum over unshadowed lights colour * light * max(0, N.L)
//  - reflection added on top: local + reflectivity * traced colour, up to 5 bounces
//  - shadow rays ignore the object being shaded (spheres and planes are convex,
//    they cannot shadow themselves where N.L > 0); reflected rays start 1e-4 off the surface
//  - texture replaces the object colour; bilinear filtering
//  - sphere texture: longitude/latitude map, u = (atan2(-z, x) + pi) / 2pi, v from acos(y)
//  - output: binary P6, colours clamped to [0,1] and rounded
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

struct Vec {
    double x, y, z;
    Vec(double a = 0, double b = 0, double c = 0) : x(a), y(b), z(c) {}
    Vec operator+(const Vec &o) const { return Vec(x + o.x, y + o.y, z + o.z); }
    Vec operator-(const Vec &o) const { return Vec(x - o.x, y - o.y, z - o.z); }
    Vec operator*(double s) const { return Vec(x * s, y * s, z * s); }
    Vec operator*(const Vec &o) const { return Vec(x * o.x, y * o.y, z * o.z); }
    Vec operator-() const { return Vec(-x, -y, -z); }
};
static double dot(const Vec &a, const Vec &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static Vec cross(const Vec &a, const Vec &b) {
    return Vec(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double len(const Vec &a) { return std::sqrt(dot(a, a)); }
static Vec norm(const Vec &a) {
    double l = len(a);
    return l > 0 ? a * (1.0 / l) : a;
}

struct Texture {
    int w = 0, h = 0;
    std::vector<Vec> px;
    bool ok() const { return w > 0 && h > 0; }
    Vec at(int i, int j) const {
        if (i < 0) i = 0;
        if (j < 0) j = 0;
        if (i >= w) i = w - 1;
        if (j >= h) j = h - 1;
        return px[j * w + i];
    }
    // s, t in [0,1], t = 0 is the top row of the image
    Vec sample(double s, double t) const {
        double x = s * w - 0.5, y = t * h - 0.5;
        int x0 = (int)std::floor(x), y0 = (int)std::floor(y);
        double fx = x - x0, fy = y - y0;
        Vec a = at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx;
        Vec b = at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx;
        return a * (1 - fy) + b * fy;
    }
};

// reads the next header token of a PPM, skipping whitespace and # comments
static bool ppmToken(std::istream &in, std::string &tok) {
    tok.clear();
    int c;
    while ((c = in.get()) != EOF) {
        if (c == '#') {
            while ((c = in.get()) != EOF && c != '\n') {}
            continue;
        }
        if (isspace(c)) {
            if (!tok.empty()) return true;
            continue;
        }
        tok += (char)c;
    }
    return !tok.empty();
}

static bool loadPPM(const std::string &path, Texture &tex) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::string magic, ws, hs, ms;
    if (!ppmToken(in, magic) || (magic != "P6" && magic != "P3")) return false;
    if (!ppmToken(in, ws) || !ppmToken(in, hs) || !ppmToken(in, ms)) return false;
    int w = atoi(ws.c_str()), h = atoi(hs.c_str()), maxv = atoi(ms.c_str());
    if (w <= 0 || h <= 0 || maxv <= 0) return false;
    tex.w = w;
    tex.h = h;
    tex.px.assign((size_t)w * h, Vec());
    for (size_t i = 0; i < (size_t)w * h; i++) {
        double c[3];
        for (int k = 0; k < 3; k++) {
            int v = 0;
            if (magic == "P3") {
                std::string t;
                if (!ppmToken(in, t)) return false;
                v = atoi(t.c_str());
            } else if (maxv < 256) {
                v = in.get();
            } else {
                int hi = in.get(), lo = in.get();
                v = hi * 256 + lo;
            }
            if (v < 0) return false;
            c[k] = (double)v / maxv;
        }
        tex.px[i] = Vec(c[0], c[1], c[2]);
    }
    return true;
}

struct Object {
    bool isPlane = false;
    Vec center;
    double radius = 1;           // sphere
    double width = 1, height = 1; // plane
    Vec normal = Vec(0, 1, 0), headup = Vec(0, 0, 1);
    Vec up, right;               // plane axes, computed after parsing
    Vec color = Vec(1, 1, 1);
    double refl = 0;
    Texture tex;
};

struct Light {
    Vec pos;
    Vec color = Vec(1, 1, 1);
};

static int resolution = 256;
static std::vector<Object> objects;
static std::vector<Light> lights;

static const double KA = 0.1;
static const int MAX_DEPTH = 2;
static const double EPS = 1e-4;
static const double TMIN = 1e-6;

static std::string dirOf(const std::string &p) {
    size_t k = p.find_last_of('/');
    return k == std::string::npos ? std::string("") : p.substr(0, k + 1);
}

static void parseScene(const std::string &file) {
    std::ifstream in(file);
    if (!in) {
        std::cerr << "cannot open scene file " << file << "\n";
        exit(1);
    }
    std::string line;
    Object *obj = nullptr;
    Light *light = nullptr;
    // reserve so pointers stay valid
    objects.reserve(1000);
    lights.reserve(1000);
    while (std::getline(in, line)) {
        size_t hash = line.find('#');
        if (hash != std::string::npos) line = line.substr(0, hash);
        std::istringstream ls(line);
        std::string key;
        if (!(ls >> key)) continue;
        if (key == "camera") {
            ls >> resolution;
            obj = nullptr;
            light = nullptr;
        } else if (key == "sphere" || key == "plane") {
            objects.push_back(Object());
            obj = &objects.back();
            obj->isPlane = (key == "plane");
            light = nullptr;
        } else if (key == "light") {
            lights.push_back(Light());
            light = &lights.back();
            obj = nullptr;
        } else if (light) {
            if (key == "location") ls >> light->pos.x >> light->pos.y >> light->pos.z;
            else if (key == "color" || key == "colour") ls >> light->color.x >> light->color.y >> light->color.z;
            else std::cerr << "warning: unknown light attribute " << key << "\n";
        } else if (obj) {
            if (key == "dimension") {
                if (obj->isPlane) ls >> obj->width >> obj->height;
                else ls >> obj->radius;
            } else if (key == "center" || key == "centre") ls >> obj->center.x >> obj->center.y >> obj->center.z;
            else if (key == "color" || key == "colour") ls >> obj->color.x >> obj->color.y >> obj->color.z;
            else if (key == "reflectivity") ls >> obj->refl;
            else if (key == "normal") ls >> obj->normal.x >> obj->normal.y >> obj->normal.z;
            else if (key == "headup") ls >> obj->headup.x >> obj->headup.y >> obj->headup.z;
            else if (key == "texture") {
                std::string name;
                ls >> name;
                std::string path = (name.size() && name[0] == '/') ? name : dirOf(file) + name;
                if (!loadPPM(path, obj->tex) && !loadPPM(name, obj->tex))
                    std::cerr << "warning: cannot read texture " << name << ", using the colour\n";
            } else std::cerr << "warning: unknown attribute " << key << "\n";
        } else {
            std::cerr << "warning: ignoring line: " << line << "\n";
        }
    }
    for (Object &o : objects) {
        if (!o.isPlane) continue;
        o.normal = norm(o.normal);
        Vec up = o.headup - o.normal * dot(o.headup, o.normal);
        if (len(up) < 1e-9) { // headup parallel to normal: pick any axis
            Vec a = std::fabs(o.normal.x) < 0.9 ? Vec(1, 0, 0) : Vec(0, 1, 0);
            up = a - o.normal * dot(a, o.normal);
        }
        o.up = norm(up);
        o.right = cross(o.up, o.normal);
    }
}

// ray: p(t) = e + t d; returns t of the nearest hit in front of e, or -1
static double intersect(const Object &o, const Vec &e, const Vec &d) {
    if (!o.isPlane) {
        Vec ec = e - o.center;
        double a = dot(d, d);
        double b = 2 * dot(d, ec);
        double c = dot(ec, ec) - o.radius * o.radius;
        double disc = b * b - 4 * a * c;
        if (disc < 0) return -1;
        double sq = std::sqrt(disc);
        double t1 = (-b - sq) / (2 * a);
        double t2 = (-b + sq) / (2 * a);
        if (t1 > TMIN) return t1;
        if (t2 > TMIN) return t2;
        return -1;
    }
    // plane: a x + b y + c z + dd = 0 with (a,b,c) the normal
    double dd = -dot(o.normal, o.center);
    double den = dot(o.normal, d);
    if (std::fabs(den) < 1e-12) return -1;
    double t = -(dot(o.normal, e) + dd) / den;
    if (t <= TMIN) return -1;
    Vec q = e + d * t - o.center;
    if (std::fabs(dot(q, o.right)) > o.width / 2 || std::fabs(dot(q, o.up)) > o.height / 2) return -1;
    return t;
}

static Vec surfaceColor(const Object &o, const Vec &p, const Vec &n) {
    if (!o.tex.ok()) return o.color;
    double s, t;
    if (o.isPlane) {
        Vec q = p - o.center;
        s = dot(q, o.right) / o.width + 0.5;
        t = 0.5 - dot(q, o.up) / o.height;
    } else {
        Vec k = norm(p - o.center);
        s = (std::atan2(-k.z, k.x) + M_PI) / (2 * M_PI);
        t = std::acos(std::max(-1.0, std::min(1.0, k.y))) / M_PI;
    }
    return o.tex.sample(s, t);
}

static Vec trace(const Vec &e, const Vec &d, int depth) {
    double best = 1e300;
    int hit = -1;
    for (size_t i = 0; i < objects.size(); i++) {
        double t = intersect(objects[i], e, d);
        if (t > 0 && t < best) {
            best = t;
            hit = (int)i;
        }
    }
    if (hit < 0) return Vec(0, 0, 0); // background
    const Object &o = objects[hit];
    Vec p = e + d * best;
    Vec n = o.isPlane ? o.normal : norm(p - o.center);
    if (dot(n, d) > 0) n = -n; // face the viewer (planes are two-sided)
    Vec col = surfaceColor(o, p, n);

    Vec result = col * KA;
    for (const Light &l : lights) {
        Vec tol = l.pos - p;
        double dist = len(tol);
        Vec L = tol * (1.0 / dist);
        double ndl = dot(n, L);
        if (ndl < 0) ndl = 0;
        bool shadow = false;
        for (size_t i = 0; i < objects.size() && !shadow; i++) {
            if ((int)i == hit) continue;
            double t = intersect(objects[i], p, L);
            if (t > 0 && t < dist) shadow = true;
        }
        if (shadow) continue;
        result = result + col * l.color * ndl;
    }

    if (o.refl > 0 && depth < MAX_DEPTH) {
        Vec v = -d;
        Vec r = norm(n * (2 * dot(n, v)) - v);
        Vec rc = trace(p + n * EPS, r, depth + 1);
        result = result + rc * o.refl;
    }
    return result;
}

static int toByte(double c) {
    if (c < 0) c = 0;
    if (c > 1) c = 1;
    return (int)(c * 255 + 0.5);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        std::cerr << "usage: " << argv[0] << " scene_description_file output_image\n";
        return 1;
    }
    parseScene(argv[1]);
    int N = resolution;
    if (N <= 0) {
        std::cerr << "bad camera resolution\n";
        return 1;
    }
    std::vector<unsigned char> img((size_t)N * N * 3);
    for (int j = 0; j < N; j++) {
        for (int i = 0; i < N; i++) {
            // pixel centre on the image plane z = -1, which spans [-0.5, 0.5]^2
            double x = -0.5 + (i + 0.5) / N;
            double y = 0.5 - (j + 0.5) / N;
            Vec d = norm(Vec(x, y, -1));
            Vec c = trace(Vec(0, 0, 0), d, 0);
            size_t k = ((size_t)j * N + i) * 3;
            img[k + 0] = (unsigned char)toByte(c.x);
            img[k + 1] = (unsigned char)toByte(c.y);
            img[k + 2] = (unsigned char)toByte(c.z);
        }
    }
    FILE *f = fopen(argv[2], "wb");
    if (!f) {
        std::cerr << "cannot write " << argv[2] << "\n";
        return 1;
    }
    fprintf(f, "P6\n%d %d\n255\n", N, N);
    fwrite(img.data(), 1, img.size(), f);
    fclose(f);
    return 0;
}
