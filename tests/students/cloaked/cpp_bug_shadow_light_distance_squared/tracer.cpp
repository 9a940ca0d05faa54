// HW4 ray tracer (C++)
// usage: ./tracer scene_file output_image
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

struct Vec {
    double x, y, z;
    Vec() : x(0), y(0), z(0) {}
    Vec(double a, double b, double c) : x(a), y(b), z(c) {}
    Vec operator+(const Vec &o) const { return Vec(x + o.x, y + o.y, z + o.z); }
    Vec operator-(const Vec &o) const { return Vec(x - o.x, y - o.y, z - o.z); }
    Vec operator*(double s) const { return Vec(x * s, y * s, z * s); }
    Vec mul(const Vec &o) const { return Vec(x * o.x, y * o.y, z * o.z); }
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

static void die(const std::string &msg) {
    std::cerr << "error: " << msg << std::endl;
    std::exit(1);
}

struct Image {
    int w = 0, h = 0;
    std::vector<Vec> px;
    Vec at(int i, int j) const { return px[(size_t)j * w + i]; }
};

// ---------- PPM texture loading (P3 / P6) ----------
static std::string nextTok(const std::string &d, size_t &p) {
    while (p < d.size()) {
        if (d[p] == '#') {
            while (p < d.size() && d[p] != '\n') p++;
        } else if (isspace((unsigned char)d[p])) {
            p++;
        } else
            break;
    }
    size_t s = p;
    while (p < d.size() && !isspace((unsigned char)d[p]) && d[p] != '#') p++;
    return d.substr(s, p - s);
}

static int tokInt(const std::string &t, const std::string &file) {
    char *end = nullptr;
    long v = std::strtol(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0') die("bad number in texture " + file);
    return (int)v;
}

static Image loadPPM(const std::string &file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) die("cannot open texture " + file);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string d = ss.str();
    size_t p = 0;
    std::string magic = nextTok(d, p);
    if (magic != "P6" && magic != "P3") die("texture is not a PPM: " + file);
    Image img;
    img.w = tokInt(nextTok(d, p), file);
    img.h = tokInt(nextTok(d, p), file);
    int maxv = tokInt(nextTok(d, p), file);
    if (img.w <= 0 || img.h <= 0 || maxv <= 0 || maxv > 65535) die("bad texture header " + file);
    size_t n = (size_t)img.w * img.h;
    img.px.resize(n);
    if (magic == "P3") {
        for (size_t i = 0; i < n; i++) {
            double c[3];
            for (int k = 0; k < 3; k++) {
                std::string t = nextTok(d, p);
                if (t.empty()) die("texture data too short " + file);
                c[k] = tokInt(t, file) / (double)maxv;
            }
            img.px[i] = Vec(c[0], c[1], c[2]);
        }
    } else {
        p++;  // single whitespace after maxval
        int bps = maxv < 256 ? 1 : 2;
        if (d.size() < p + n * 3 * bps) die("texture data too short " + file);
        for (size_t i = 0; i < n; i++) {
            double c[3];
            for (int k = 0; k < 3; k++) {
                unsigned v;
                if (bps == 1)
                    v = (unsigned char)d[p++];
                else {
                    v = ((unsigned char)d[p] << 8) | (unsigned char)d[p + 1];
                    p += 2;
                }
                c[k] = v / (double)maxv;
            }
            img.px[i] = Vec(c[0], c[1], c[2]);
        }
    }
    return img;
}

// ---------- scene ----------
enum Kind { SPHERE, PLANE };

struct Object {
    Kind kind;
    double dim[2] = {1, 1};
    Vec center;
    Vec color = Vec(1, 1, 1);
    double refl = 0;
    Vec normal = Vec(0, 0, 1);
    Vec headup = Vec(0, 1, 0);
    int tex = -1;
    // derived plane frame
    Vec n, up, right;
    double radius = 1;
};

struct Light {
    Vec pos;
    Vec color = Vec(1, 1, 1);
};

struct Scene {
    int res = 0;
    std::vector<Object> objs;
    std::vector<Light> lights;
    std::vector<Image> textures;
};

static double toNum(const std::string &t) {
    char *end = nullptr;
    double v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v)) die("bad number '" + t + "'");
    return v;
}

static Scene parseScene(const std::string &path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) die("cannot open scene " + path);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string d = ss.str();
    // unicode line/paragraph separators and nbsp count as whitespace
    for (size_t i = 0; i + 2 < d.size(); i++) {
        if ((unsigned char)d[i] == 0xE2 && (unsigned char)d[i + 1] == 0x80 &&
            ((unsigned char)d[i + 2] == 0xA8 || (unsigned char)d[i + 2] == 0xA9)) {
            d[i] = d[i + 1] = d[i + 2] = ' ';
        }
    }
    for (size_t i = 0; i + 1 < d.size(); i++)
        if ((unsigned char)d[i] == 0xC2 && (unsigned char)d[i + 1] == 0xA0) d[i] = d[i + 1] = ' ';

    std::string dir;
    size_t slash = path.find_last_of('/');
    if (slash != std::string::npos) dir = path.substr(0, slash + 1);

    std::vector<std::string> toks;
    {
        std::istringstream ts(d);
        std::string t;
        while (ts >> t) toks.push_back(t);
    }
    Scene sc;
    bool haveCam = false;
    enum { NONE, OBJ, LIGHT } cur = NONE;
    size_t i = 0;
    auto need = [&](const std::string &kw) -> std::string {
        if (i >= toks.size()) die("missing value after " + kw);
        return toks[i++];
    };
    auto vec3 = [&](const std::string &kw) {
        double a = toNum(need(kw));
        double b = toNum(need(kw));
        double c = toNum(need(kw));
        return Vec(a, b, c);
    };
    while (i < toks.size()) {
        std::string kw = toks[i++];
        if (kw == "camera") {
            std::string t = need(kw);
            char *end = nullptr;
            long r = std::strtol(t.c_str(), &end, 10);
            if (t.empty() || *end != '\0' || r <= 0 || r > 20000) die("bad camera resolution '" + t + "'");
            sc.res = (int)r;
            haveCam = true;
            cur = NONE;
        } else if (kw == "sphere" || kw == "plane") {
            Object o;
            o.kind = kw == "sphere" ? SPHERE : PLANE;
            if (o.kind == PLANE) o.dim[0] = o.dim[1] = 1;
            sc.objs.push_back(o);
            cur = OBJ;
        } else if (kw == "light") {
            sc.lights.push_back(Light());
            cur = LIGHT;
        } else if (cur == OBJ && kw == "dimension") {
            Object &o = sc.objs.back();
            o.dim[0] = toNum(need(kw));
            if (o.kind == PLANE) o.dim[1] = toNum(need(kw));
        } else if (cur == OBJ && kw == "center") {
            sc.objs.back().center = vec3(kw);
        } else if (cur == OBJ && kw == "color") {
            sc.objs.back().color = vec3(kw);
        } else if (cur == OBJ && kw == "reflectivity") {
            sc.objs.back().refl = toNum(need(kw));
        } else if (cur == OBJ && kw == "normal" && sc.objs.back().kind == PLANE) {
            sc.objs.back().normal = vec3(kw);
        } else if (cur == OBJ && kw == "headup" && sc.objs.back().kind == PLANE) {
            sc.objs.back().headup = vec3(kw);
        } else if (cur == OBJ && kw == "texture") {
            std::string f = need(kw);
            std::string full = (!f.empty() && f[0] == '/') ? f : dir + f;
            sc.textures.push_back(loadPPM(full));
            sc.objs.back().tex = (int)sc.textures.size() - 1;
        } else if (cur == LIGHT && kw == "location") {
            sc.lights.back().pos = vec3(kw);
        } else if (cur == LIGHT && kw == "color") {
            sc.lights.back().color = vec3(kw);
        } else {
            die("unknown or misplaced keyword '" + kw + "'");
        }
    }
    if (!haveCam) die("no camera line in scene");

    for (Object &o : sc.objs) {
        if (o.kind == SPHERE) {
            o.radius = o.dim[0];
            if (o.radius <= 0) die("sphere dimension must be positive");
        } else {
            if (len(o.normal) == 0) die("plane normal is zero");
            o.n = norm(o.normal);
            Vec u = o.headup - o.n * dot(o.headup, o.n);
            if (len(u) < 1e-9) {
                // headup parallel to normal: pick any perpendicular direction
                Vec a = std::fabs(o.n.y) < 0.9 ? Vec(0, 1, 0) : Vec(0, 0, -1);
                u = a - o.n * dot(a, o.n);
            }
            o.up = norm(u);
            o.right = norm(cross(o.up, o.n));
        }
    }
    return sc;
}

// ---------- intersection ----------
static const double EPS = 1e-4;
static const int MAX_DEPTH = 5;
static const double KA = 0.1;

static bool hitObject(const Object &o, const Vec &orig, const Vec &dir, double &t) {
    if (o.kind == SPHERE) {
        Vec oc = orig - o.center;
        double a = dot(dir, dir);
        double b = 2 * dot(dir, oc);
        double c = dot(oc, oc) - o.radius * o.radius;
        double disc = b * b - 4 * a * c;
        if (disc < 0) return false;
        double sq = std::sqrt(disc);
        double t1 = (-b - sq) / (2 * a), t2 = (-b + sq) / (2 * a);
        if (t1 > EPS) {
            t = t1;
            return true;
        }
        if (t2 > EPS) {
            t = t2;
            return true;
        }
        return false;
    } else {
        double den = dot(o.n, dir);
        if (std::fabs(den) < 1e-12) return false;
        double dd = -dot(o.n, o.center);
        double tt = -(dot(o.n, orig) + dd) / den;
        if (tt <= EPS) return false;
        Vec p = orig + dir * tt;
        Vec q = p - o.center;
        if (std::fabs(dot(q, o.right)) > o.dim[0] / 2 || std::fabs(dot(q, o.up)) > o.dim[1] / 2) return false;
        t = tt;
        return true;
    }
}

static int closest(const Scene &sc, const Vec &orig, const Vec &dir, double &tBest) {
    int best = -1;
    tBest = 1e300;
    for (size_t k = 0; k < sc.objs.size(); k++) {
        double t;
        if (hitObject(sc.objs[k], orig, dir, t) && t < tBest) {
            tBest = t;
            best = (int)k;
        }
    }
    return best;
}

static Vec texel(const Image &img, double u, double v) {
    u -= std::floor(u);
    v -= std::floor(v);
    int i = (int)(u * img.w), j = (int)(v * img.h);
    if (i >= img.w) i = img.w - 1;
    if (j >= img.h) j = img.h - 1;
    return img.at(i, j);
}

static Vec surfaceColor(const Scene &sc, const Object &o, const Vec &p, const Vec &n) {
    if (o.tex < 0) return o.color;
    const Image &img = sc.textures[o.tex];
    double u, v;
    if (o.kind == SPHERE) {
        u = 0.5 + std::atan2(n.z, n.x) / (2 * M_PI);
        v = 0.5 - std::asin(std::max(-1.0, std::min(1.0, n.y))) / M_PI;
    } else {
        Vec q = p - o.center;
        u = dot(q, o.right) / o.dim[0] + 0.5;
        v = 0.5 - dot(q, o.up) / o.dim[1];
    }
    return texel(img, u, v);
}

static Vec trace(const Scene &sc, const Vec &orig, const Vec &dir, int depth) {
    double t;
    int k = closest(sc, orig, dir, t);
    if (k < 0) return Vec(0, 0, 0);
    const Object &o = sc.objs[k];
    Vec p = orig + dir * t;
    Vec n = o.kind == SPHERE ? norm(p - o.center) : o.n;
    if (dot(n, dir) > 0) n = n * -1.0;  // face the viewer (planes are two-sided)
    Vec base = surfaceColor(sc, o, p, n);

    Vec col = base * KA;
    for (const Light &l : sc.lights) {
        Vec toL = l.pos - p;
        double dist2 = dot(toL, toL);
        double dist = std::sqrt(dist2);
        Vec L = toL * (1.0 / dist);
        double ndl = dot(n, L);
        if (ndl <= 0) continue;
        Vec so = p + n * EPS;
        bool blocked = false;
        for (const Object &ob : sc.objs) {
            double ts;
            if (hitObject(ob, so, L, ts)) {
                if (ts > EPS && ts < dist2) {
                    blocked = true;
                    break;
                }
            }
        }
        if (blocked) continue;
        col = col + base.mul(l.color) * ndl;
    }

    if (o.refl > 0 && depth < MAX_DEPTH) {
        Vec v = dir * -1.0;
        Vec r = norm(n * (2 * dot(n, v)) - v);
        Vec rc = trace(sc, p + n * EPS, r, depth + 1);
        col = col + rc * o.refl;
    }
    return col;
}

static unsigned char toByte(double c) {
    if (c < 0) c = 0;
    if (c > 1) c = 1;
    return (unsigned char)(int)(c * 255.0 + 0.5);
}

int main(int argc, char **argv) {
    if (argc != 3) {
        std::cerr << "usage: " << argv[0] << " scene_file output_image" << std::endl;
        return 1;
    }
    Scene sc = parseScene(argv[1]);
    int N = sc.res;
    std::vector<unsigned char> out((size_t)N * N * 3);
    Vec eye(0, 0, 0);
    for (int j = 0; j < N; j++) {
        for (int i = 0; i < N; i++) {
            double x = -0.5 + (i + 0.5) / N;
            double y = 0.5 - (j + 0.5) / N;
            Vec dir = norm(Vec(x, y, -1));
            Vec c = trace(sc, eye, dir, 0);
            size_t idx = ((size_t)j * N + i) * 3;
            out[idx] = toByte(c.x);
            out[idx + 1] = toByte(c.y);
            out[idx + 2] = toByte(c.z);
        }
    }
    FILE *f = std::fopen(argv[2], "wb");
    if (!f) die(std::string("cannot write ") + argv[2]);
    std::fprintf(f, "P6\n%d %d\n255\n", N, N);
    std::fwrite(out.data(), 1, out.size(), f);
    std::fclose(f);
    return 0;
}
