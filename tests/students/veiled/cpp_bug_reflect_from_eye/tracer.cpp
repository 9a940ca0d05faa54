// HW4 ray tracer
// usage: ./tracer scene_description_file output_image
//
// Reads the scene format from the handout (camera / sphere / plane / light sections),
// traces one ray per pixel with shadow rays and recursive mirror reflection,
// and writes a binary PPM (P6) image.

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

// ---------------------------------------------------------------------------
// small vector type

struct Vec {
    double x = 0, y = 0, z = 0;
    Vec() {}
    Vec(double a, double b, double c) : x(a), y(b), z(c) {}
    Vec operator+(const Vec& o) const { return Vec(x + o.x, y + o.y, z + o.z); }
    Vec operator-(const Vec& o) const { return Vec(x - o.x, y - o.y, z - o.z); }
    Vec operator*(double s) const { return Vec(x * s, y * s, z * s); }
    Vec operator*(const Vec& o) const { return Vec(x * o.x, y * o.y, z * o.z); }
    Vec operator-() const { return Vec(-x, -y, -z); }
    Vec& operator+=(const Vec& o) { x += o.x; y += o.y; z += o.z; return *this; }
};

static double dot(const Vec& a, const Vec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static Vec cross(const Vec& a, const Vec& b) {
    return Vec(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static double length(const Vec& a) { return std::sqrt(dot(a, a)); }
static Vec normalize(const Vec& a) {
    double l = length(a);
    return l > 0 ? a * (1.0 / l) : a;
}

// ---------------------------------------------------------------------------
// errors: print a message and leave with exit code 1 (no output file is written
// because the image is only written after everything succeeded)

[[noreturn]] static void fail(const std::string& msg) {
    std::cerr << "error: " << msg << std::endl;
    std::exit(1);
}

// ---------------------------------------------------------------------------
// textures (PPM P3 / P6)

struct Texture {
    int w = 0, h = 0;
    std::vector<Vec> pix;  // row 0 = top row of the file

    // nearest texel, u to the right, v downwards, both in [0,1]
    Vec lookup(double u, double v) const {
        if (u < 0) u = 0;
        if (u > 1) u = 1;
        if (v < 0) v = 0;
        if (v > 1) v = 1;
        int i = (int)(u * w);
        int j = (int)(v * h);
        if (i >= w) i = w - 1;
        if (j >= h) j = h - 1;
        return pix[(size_t)j * w + i];
    }
};

// reads the next header token of a PPM file, skipping whitespace and # comments
static bool ppmToken(const std::string& data, size_t& pos, std::string& tok) {
    tok.clear();
    while (pos < data.size()) {
        char c = data[pos];
        if (c == '#') {
            while (pos < data.size() && data[pos] != '\n' && data[pos] != '\r') pos++;
        } else if (std::isspace((unsigned char)c)) {
            pos++;
        } else {
            break;
        }
    }
    while (pos < data.size() && !std::isspace((unsigned char)data[pos]) && data[pos] != '#') {
        tok += data[pos++];
    }
    return !tok.empty();
}

static bool ppmInt(const std::string& data, size_t& pos, long& out) {
    std::string tok;
    if (!ppmToken(data, pos, tok)) return false;
    for (char c : tok)
        if (c < '0' || c > '9') return false;
    if (tok.size() > 9) return false;
    out = std::stol(tok);
    return true;
}

static bool loadPPM(const std::string& path, Texture& tex, std::string& why) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        why = "cannot open";
        return false;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    std::string data = ss.str();
    size_t pos = 0;
    std::string magic;
    if (!ppmToken(data, pos, magic) || (magic != "P3" && magic != "P6")) {
        why = "not a P3/P6 PPM file";
        return false;
    }
    long w, h, maxv;
    if (!ppmInt(data, pos, w) || !ppmInt(data, pos, h) || !ppmInt(data, pos, maxv) || w <= 0 || h <= 0 ||
        maxv <= 0 || maxv > 65535) {
        why = "bad PPM header";
        return false;
    }
    if (w * h > 100000000L) {
        why = "texture too large";
        return false;
    }
    tex.w = (int)w;
    tex.h = (int)h;
    tex.pix.assign((size_t)w * h, Vec());
    size_t n = (size_t)w * h * 3;
    std::vector<double> vals(n);
    if (magic == "P3") {
        for (size_t k = 0; k < n; k++) {
            long v;
            if (!ppmInt(data, pos, v)) {
                why = "truncated or bad P3 data";
                return false;
            }
            vals[k] = (double)v / (double)maxv;
        }
    } else {
        pos++;  // exactly one whitespace after maxval
        size_t bytes = maxv > 255 ? 2 : 1;
        if (pos + n * bytes > data.size()) {
            why = "truncated P6 data";
            return false;
        }
        for (size_t k = 0; k < n; k++) {
            long v;
            if (bytes == 1) {
                v = (unsigned char)data[pos + k];
            } else {
                v = ((unsigned char)data[pos + 2 * k] << 8) | (unsigned char)data[pos + 2 * k + 1];
            }
            vals[k] = (double)v / (double)maxv;
        }
    }
    for (size_t k = 0; k < (size_t)w * h; k++) tex.pix[k] = Vec(vals[3 * k], vals[3 * k + 1], vals[3 * k + 2]);
    return true;
}

// ---------------------------------------------------------------------------
// scene

enum Kind { SPHERE, PLANE };

struct Object {
    Kind kind;
    Vec center;
    double radius = 0;  // sphere: "dimension r"
    double w = 0, h = 0;  // plane: "dimension w h"
    Vec normal, headup;
    Vec right, up;  // plane frame (built after parsing)
    Vec color = Vec(1, 1, 1);
    double reflectivity = 0;
    const Texture* tex = nullptr;
    bool hasCenter = false, hasDim = false, hasNormal = false, hasHeadup = false;
};

struct Light {
    Vec pos;
    Vec color = Vec(1, 1, 1);
    bool hasPos = false;
};

struct Scene {
    int res = 0;
    std::vector<Object> objects;
    std::vector<Light> lights;
    std::map<std::string, std::unique_ptr<Texture>> textures;
};

static std::string trim(const std::string& s) {
    size_t a = s.find_first_not_of(" \t\r\n\f\v");
    if (a == std::string::npos) return "";
    size_t b = s.find_last_not_of(" \t\r\n\f\v");
    return s.substr(a, b - a + 1);
}

static double toNumber(const std::string& tok, int line) {
    const char* s = tok.c_str();
    char* end = nullptr;
    double v = std::strtod(s, &end);
    if (end == s || *end != '\0' || !std::isfinite(v))
        fail("line " + std::to_string(line) + ": '" + tok + "' is not a number");
    return v;
}

static std::vector<double> numbers(const std::vector<std::string>& toks, size_t want, int line) {
    if (toks.size() - 1 != want)
        fail("line " + std::to_string(line) + ": '" + toks[0] + "' expects " + std::to_string(want) +
             " number(s), got " + std::to_string(toks.size() - 1));
    std::vector<double> v;
    for (size_t i = 1; i < toks.size(); i++) v.push_back(toNumber(toks[i], line));
    return v;
}

static std::string dirOf(const std::string& path) {
    size_t p = path.find_last_of('/');
    if (p == std::string::npos) return "";
    return path.substr(0, p + 1);
}

static const Texture* getTexture(Scene& sc, const std::string& name, const std::string& sceneDir, int line) {
    std::vector<std::string> tries;
    if (!name.empty() && name[0] == '/') {
        tries.push_back(name);
    } else {
        tries.push_back(sceneDir + name);
        tries.push_back(name);
    }
    std::string why = "not found";
    for (const std::string& p : tries) {
        auto it = sc.textures.find(p);
        if (it != sc.textures.end()) return it->second.get();
        std::ifstream test(p, std::ios::binary);
        if (!test) continue;
        std::unique_ptr<Texture> t(new Texture);
        if (!loadPPM(p, *t, why))
            fail("line " + std::to_string(line) + ": texture '" + name + "': " + why);
        const Texture* raw = t.get();
        sc.textures[p] = std::move(t);
        return raw;
    }
    fail("line " + std::to_string(line) + ": texture '" + name + "' " + why);
}

static void finishObject(Object& o) {
    if (!o.hasCenter) fail("object without center");
    if (!o.hasDim) fail("object without dimension");
    if (o.kind == SPHERE) {
        if (o.radius <= 0) fail("sphere dimension must be positive");
        return;
    }
    if (o.w <= 0 || o.h <= 0) fail("plane dimension must be positive");
    if (!o.hasNormal) fail("plane without normal");
    if (length(o.normal) < 1e-12) fail("plane normal is zero");
    o.normal = normalize(o.normal);
    Vec hu = o.hasHeadup ? o.headup : Vec(0, 1, 0);
    Vec up = hu - o.normal * dot(hu, o.normal);
    if (length(up) < 1e-9) {
        // headup parallel to the normal (or missing): pick something perpendicular
        hu = std::fabs(o.normal.y) < 0.9 ? Vec(0, 1, 0) : Vec(0, 0, -1);
        up = hu - o.normal * dot(hu, o.normal);
    }
    o.up = normalize(up);
    o.right = normalize(cross(o.up, o.normal));
}

static void parseScene(const std::string& file, Scene& sc) {
    std::ifstream in(file, std::ios::binary);
    if (!in) fail("cannot read scene file '" + file + "'");
    std::string sceneDir = dirOf(file);
    enum { NONE, OBJ, LIGHT } section = NONE;
    bool haveCamera = false;
    std::string raw;
    int lineNo = 0;
    auto closeSection = [&]() {
        if (section == OBJ) finishObject(sc.objects.back());
        if (section == LIGHT && !sc.lights.back().hasPos) fail("light without location");
        section = NONE;
    };
    while (std::getline(in, raw)) {
        lineNo++;
        std::string line = trim(raw);
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        std::vector<std::string> toks;
        std::string t;
        while (ls >> t) toks.push_back(t);
        const std::string& key = toks[0];

        if (key == "camera") {
            closeSection();
            if (haveCamera) fail("more than one camera");
            std::vector<double> v = numbers(toks, 1, lineNo);
            if (v[0] < 1 || v[0] != std::floor(v[0]) || v[0] > 20000)
                fail("camera resolution must be a positive whole number");
            sc.res = (int)v[0];
            haveCamera = true;
        } else if (key == "sphere" || key == "plane") {
            closeSection();
            numbers(toks, 0, lineNo);
            Object o;
            o.kind = key == "sphere" ? SPHERE : PLANE;
            sc.objects.push_back(o);
            section = OBJ;
        } else if (key == "light") {
            closeSection();
            numbers(toks, 0, lineNo);
            sc.lights.push_back(Light());
            section = LIGHT;
        } else if (section == OBJ) {
            Object& o = sc.objects.back();
            if (key == "dimension") {
                if (o.kind == SPHERE) {
                    o.radius = numbers(toks, 1, lineNo)[0];
                } else {
                    std::vector<double> v = numbers(toks, 2, lineNo);
                    o.w = v[0];
                    o.h = v[1];
                }
                o.hasDim = true;
            } else if (key == "center") {
                std::vector<double> v = numbers(toks, 3, lineNo);
                o.center = Vec(v[0], v[1], v[2]);
                o.hasCenter = true;
            } else if (key == "color") {
                std::vector<double> v = numbers(toks, 3, lineNo);
                o.color = Vec(v[0], v[1], v[2]);
            } else if (key == "reflectivity") {
                o.reflectivity = numbers(toks, 1, lineNo)[0];
            } else if (key == "texture") {
                std::string name = trim(line.substr(key.size()));
                if (name.empty()) fail("line " + std::to_string(lineNo) + ": texture needs a file name");
                o.tex = getTexture(sc, name, sceneDir, lineNo);
            } else if (o.kind == PLANE && key == "normal") {
                std::vector<double> v = numbers(toks, 3, lineNo);
                o.normal = Vec(v[0], v[1], v[2]);
                o.hasNormal = true;
            } else if (o.kind == PLANE && key == "headup") {
                std::vector<double> v = numbers(toks, 3, lineNo);
                o.headup = Vec(v[0], v[1], v[2]);
                o.hasHeadup = true;
            } else {
                fail("line " + std::to_string(lineNo) + ": unknown keyword '" + key + "'");
            }
        } else if (section == LIGHT) {
            Light& l = sc.lights.back();
            if (key == "location") {
                std::vector<double> v = numbers(toks, 3, lineNo);
                l.pos = Vec(v[0], v[1], v[2]);
                l.hasPos = true;
            } else if (key == "color") {
                std::vector<double> v = numbers(toks, 3, lineNo);
                l.color = Vec(v[0], v[1], v[2]);
            } else {
                fail("line " + std::to_string(lineNo) + ": unknown keyword '" + key + "'");
            }
        } else {
            fail("line " + std::to_string(lineNo) + ": unknown keyword '" + key + "'");
        }
    }
    if (in.bad()) fail("error while reading scene file");
    closeSection();
    if (!haveCamera) fail("scene has no camera");
}

// ---------------------------------------------------------------------------
// ray tracing

static const double PI = 3.14159265358979323846;
static const double EPS = 1e-4;
static const int MAX_DEPTH = 5;
static const double AMBIENT = 0.1;

// smallest t > EPS where the ray o + t d meets the object, or -1
static double intersect(const Object& ob, const Vec& o, const Vec& d) {
    if (ob.kind == SPHERE) {
        Vec oc = o - ob.center;
        double a = dot(d, d);
        double b = 2 * dot(d, oc);
        double c = dot(oc, oc) - ob.radius * ob.radius;
        double disc = b * b - 4 * a * c;
        if (disc < 0) return -1;
        double sq = std::sqrt(disc);
        double t1 = (-b - sq) / (2 * a);
        double t2 = (-b + sq) / (2 * a);
        if (t1 > EPS) return t1;
        if (t2 > EPS) return t2;
        return -1;
    }
    double denom = dot(ob.normal, d);
    if (std::fabs(denom) < 1e-12) return -1;
    double t = dot(ob.center - o, ob.normal) / denom;
    if (t <= EPS) return -1;
    Vec q = o + d * t - ob.center;
    if (std::fabs(dot(q, ob.right)) > ob.w / 2 || std::fabs(dot(q, ob.up)) > ob.h / 2) return -1;
    return t;
}

struct Hit {
    const Object* obj = nullptr;
    double t = 0;
};

static Hit closest(const Scene& sc, const Vec& o, const Vec& d) {
    Hit best;
    for (const Object& ob : sc.objects) {
        double t = intersect(ob, o, d);
        if (t > 0 && (best.obj == nullptr || t < best.t)) {
            best.obj = &ob;
            best.t = t;
        }
    }
    return best;
}

// is anything between point o and o + seg (seg = vector to the light)?
static bool inShadow(const Scene& sc, const Vec& o, const Vec& seg) {
    double dist = length(seg);
    Vec dir = seg * (1.0 / dist);
    for (const Object& ob : sc.objects) {
        double t = intersect(ob, o, dir);
        if (t > 0 && t < dist) return true;
    }
    return false;
}

static Vec surfaceColor(const Object& ob, const Vec& p) {
    if (!ob.tex) return ob.color;
    double u, v;
    if (ob.kind == SPHERE) {
        Vec q = (p - ob.center) * (1.0 / ob.radius);
        double y = q.y;
        if (y > 1) y = 1;
        if (y < -1) y = -1;
        u = 0.5 + std::atan2(q.z, q.x) / (2 * PI);
        v = std::acos(y) / PI;
    } else {
        Vec q = p - ob.center;
        u = 0.5 + dot(q, ob.right) / ob.w;
        v = 0.5 - dot(q, ob.up) / ob.h;
    }
    return ob.tex->lookup(u, v);
}

static Vec trace(const Scene& sc, const Vec& o, const Vec& d, int depth) {
    Hit hit = closest(sc, o, d);
    if (!hit.obj) return Vec(0, 0, 0);  // background
    const Object& ob = *hit.obj;
    Vec p = o + d * hit.t;
    Vec n = ob.kind == SPHERE ? normalize(p - ob.center) : ob.normal;
    if (dot(n, d) > 0) n = -n;  // face the incoming ray (two-sided planes)

    Vec kd = surfaceColor(ob, p);
    Vec col = kd * AMBIENT;
    Vec shadowOrigin = p + n * EPS;
    for (const Light& l : sc.lights) {
        Vec toLight = l.pos - p;
        Vec L = normalize(toLight);
        double ndl = dot(n, L);
        if (ndl <= 0) continue;
        if (inShadow(sc, shadowOrigin, l.pos - shadowOrigin)) continue;
        col += l.color * kd * ndl;
    }

    if (ob.reflectivity > 0 && depth < MAX_DEPTH) {
        Vec r = d - n * (2 * dot(d, n));
        Vec reflOrigin = o;
        col += trace(sc, reflOrigin, normalize(r), depth + 1) * ob.reflectivity;
    }
    return col;
}

static unsigned char toByte(double c) {
    if (c < 0) c = 0;
    if (c > 1) c = 1;
    return (unsigned char)(c * 255.0 + 0.5);
}

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: " << argv[0] << " scene_description_file output_image" << std::endl;
        return 1;
    }
    Scene sc;
    parseScene(argv[1], sc);

    int N = sc.res;
    std::vector<unsigned char> img((size_t)N * N * 3);
    for (int j = 0; j < N; j++) {
        for (int i = 0; i < N; i++) {
            // centre of the pixel on the 1x1 image plane at z = -1
            double x = -0.5 + (i + 0.5) / N;
            double y = 0.5 - (j + 0.5) / N;
            Vec d = normalize(Vec(x, y, -1));
            Vec c = trace(sc, Vec(0, 0, 0), d, 0);
            size_t k = ((size_t)j * N + i) * 3;
            img[k] = toByte(c.x);
            img[k + 1] = toByte(c.y);
            img[k + 2] = toByte(c.z);
        }
    }

    FILE* f = std::fopen(argv[2], "wb");
    if (!f) fail(std::string("cannot write '") + argv[2] + "'");
    std::fprintf(f, "P6\n%d %d\n255\n", N, N);
    size_t wrote = std::fwrite(img.data(), 1, img.size(), f);
    bool ok = wrote == img.size();
    if (std::fclose(f) != 0) ok = false;
    if (!ok) {
        std::remove(argv[2]);
        fail(std::string("failed writing '") + argv[2] + "'");
    }
    return 0;
}
