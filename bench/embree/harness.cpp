// The Embree side of `make bench`: renders a scene with Embree 3's
// single-ray API (rtcIntersect1 / rtcOccluded1), or with its camera rays in
// packets (rtcIntersect8, `--packets`), on one thread, with the render
// model of docs/rendering.md, so its time stands beside ours.
//
// Input is canonical scene text (`raytracer convert SCENE --to scene`):
// one `camera N`, then `sphere`, `plane` and `light` sections whose
// attributes are one per line. Spheres are Embree's built-in
// RTC_GEOMETRY_TYPE_SPHERE_POINT, each finite plane two triangles.
// Shading is the tracer's (crates/render/src/render/trace.rs): ambient 0.1·C plus
// C ⊙ I · max(0, N·L̂) per light a shadow ray reaches, mirror reflection
// up to MAX_DEPTH times, nearest-texel textures (PPM only), the same
// skips of work that cannot change an 8-bit value. Geometry is single
// precision (Embree's); colours are double, as ours.
//
// With --packets (before SCENE), camera rays go through Embree's packet API
// instead, as its users trace coherent rays: tiles of 4×2 pixels, eight
// camera rays per rtcIntersect8 (8 is the widest packet Debian's build
// runs natively on AVX2), each ray's path then on as before.
//
// Usage: harness [--packets] SCENE OUT.ppm [COMPARE.ppm...]
// Prints `key value` lines: the rays cast and the seconds spent building
// (rtcCommitScene) and tracing; then for each COMPARE image a line
// `diff PATH MAX MEAN`, the largest and mean absolute difference from it
// in 8-bit steps over all channels.
// Errors go to stderr with exit code 2.

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr int MAX_DEPTH = 8;
constexpr double AMBIENT = 0.1;
constexpr float OFFSET_ULPS = 64.0f;
constexpr float SHADOW_REACH = 1.0f - 512.0f * std::numeric_limits<float>::epsilon();

struct V3 {
  float x = 0, y = 0, z = 0;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
float length(V3 a) { return std::sqrt(dot(a, a)); }
V3 normalize(V3 a) { return a * (1.0f / length(a)); }
float max_abs(V3 a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }

struct Color {
  double r = 0, g = 0, b = 0;
};
Color operator+(Color a, Color b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
Color operator*(Color a, Color b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
Color operator*(Color a, double s) { return {a.r * s, a.g * s, a.b * s}; }
bool is_black(Color c) { return c.r == 0 && c.g == 0 && c.b == 0; }
bool saturated(Color c) { return std::min({c.r, c.g, c.b}) >= 1.0; }

struct Texture {
  int width = 0, height = 0;
  std::vector<Color> texels;
};

struct Material {
  Color color{1, 1, 1};
  double reflectivity = 0;
  int texture = -1;  // index into Scene::textures
};

struct Sphere {
  V3 center;
  float radius = 0;
  Material material;
};

struct Rect {
  V3 center, normal, right, up;
  float half_width = 0, half_height = 0;
  Material material;
};

struct Light {
  V3 position;
  Color color;
};

struct Scene {
  int resolution = 0;
  std::vector<Sphere> spheres;
  std::vector<Rect> rects;
  std::vector<Light> lights;
  std::vector<Texture> textures;
};

[[noreturn]] void fail(const std::string& message) {
  std::fprintf(stderr, "harness: %s\n", message.c_str());
  std::exit(2);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot read `" + path + "`");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A binary (P6) or plain (P3) PPM, scaled to [0, 1] by its maxval.
Texture read_ppm(const std::string& path) {
  std::string data = slurp(path);
  size_t at = 0;
  auto token = [&]() {
    for (;;) {
      while (at < data.size() && std::isspace(static_cast<unsigned char>(data[at]))) at++;
      if (at < data.size() && data[at] == '#') {
        while (at < data.size() && data[at] != '\n') at++;
      } else {
        break;
      }
    }
    size_t start = at;
    while (at < data.size() && !std::isspace(static_cast<unsigned char>(data[at]))) at++;
    return data.substr(start, at - start);
  };
  std::string magic = token();
  if (magic != "P6" && magic != "P3") fail("`" + path + "`: only PPM textures are supported");
  Texture t;
  t.width = std::stoi(token());
  t.height = std::stoi(token());
  int maxval = std::stoi(token());
  size_t count = size_t(t.width) * t.height * 3;
  std::vector<double> values(count);
  if (magic == "P6") {
    at++;  // the single whitespace after maxval
    int bytes = maxval > 255 ? 2 : 1;
    if (data.size() < at + count * bytes) fail("`" + path + "`: truncated");
    for (size_t i = 0; i < count; i++) {
      const unsigned char* p = reinterpret_cast<const unsigned char*>(data.data()) + at + i * bytes;
      values[i] = (bytes == 2 ? (p[0] << 8 | p[1]) : p[0]) / double(maxval);
    }
  } else {
    for (size_t i = 0; i < count; i++) values[i] = std::stoi(token()) / double(maxval);
  }
  for (size_t i = 0; i < count; i += 3) t.texels.push_back({values[i], values[i + 1], values[i + 2]});
  return t;
}

std::string folder_of(const std::string& path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// Canonical scene text: a section keyword at the start of a line, its
// attributes on the indented lines below.
Scene read_scene(const std::string& path) {
  std::istringstream in(slurp(path));
  Scene scene;
  std::string line, section;
  Sphere sphere;
  Rect rect;
  V3 normal, headup;
  float width = 0, height = 0;
  Light light;
  auto finish = [&]() {
    if (section == "sphere") {
      scene.spheres.push_back(sphere);
    } else if (section == "plane") {
      // As ir::lower: unit normal, `up` the headup projected onto the
      // plane, `right = up × n`.
      V3 n = normalize(normal);
      V3 up = normalize(headup - n * dot(headup, n));
      rect.normal = n;
      rect.up = up;
      rect.right = cross(up, n);
      rect.half_width = width / 2;
      rect.half_height = height / 2;
      scene.rects.push_back(rect);
    } else if (section == "light") {
      scene.lights.push_back(light);
    }
    sphere = Sphere();
    rect = Rect();
    light = Light();
  };
  auto v3 = [](std::istringstream& words) {
    V3 v;
    words >> v.x >> v.y >> v.z;
    return v;
  };
  auto color = [](std::istringstream& words) {
    Color c;
    words >> c.r >> c.g >> c.b;
    return c;
  };
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    if (!(words >> key) || key[0] == '#') continue;
    bool attribute = std::isspace(static_cast<unsigned char>(line[0]));
    if (!attribute) {
      finish();
      section = key;
      if (key == "camera") words >> scene.resolution;
      continue;
    }
    Material& material = section == "sphere" ? sphere.material : rect.material;
    if (key == "dimension" && section == "sphere") {
      words >> sphere.radius;
    } else if (key == "dimension") {
      words >> width >> height;
    } else if (key == "center") {
      (section == "sphere" ? sphere.center : rect.center) = v3(words);
    } else if (key == "normal") {
      normal = v3(words);
    } else if (key == "headup") {
      headup = v3(words);
    } else if (key == "location") {
      light.position = v3(words);
    } else if (key == "color" && section == "light") {
      light.color = color(words);
    } else if (key == "color") {
      material.color = color(words);
    } else if (key == "reflectivity") {
      words >> material.reflectivity;
    } else if (key == "texture") {
      std::string name;
      std::getline(words >> std::ws, name);
      if (name.size() >= 2 && name.front() == '"') name = name.substr(1, name.size() - 2);
      if (name[0] != '/') name = folder_of(path) + name;
      scene.textures.push_back(read_ppm(name));
      material.texture = int(scene.textures.size()) - 1;
    } else {
      fail("unknown attribute `" + key + "` in `" + path + "`");
    }
  }
  finish();
  if (scene.resolution < 1) fail("`" + path + "` has no camera");
  return scene;
}

struct Counters {
  unsigned long long primary = 0, shadow = 0, reflection = 0;
};

// The scene in Embree, and the tracer over it.
class Tracer {
 public:
  Tracer(const Scene& scene, RTCDevice device) : scene_(scene) {
    rtc_ = rtcNewScene(device);
    if (!scene.spheres.empty()) {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      float* v = static_cast<float*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), scene.spheres.size()));
      for (const Sphere& s : scene.spheres) {
        *v++ = s.center.x, *v++ = s.center.y, *v++ = s.center.z, *v++ = s.radius;
      }
      rtcCommitGeometry(g);
      sphere_geometry_ = rtcAttachGeometry(rtc_, g);
      rtcReleaseGeometry(g);
    }
    if (!scene.rects.empty()) {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      size_t n = scene.rects.size();
      float* v = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * n));
      unsigned* index = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2 * n));
      for (unsigned i = 0; i < n; i++) {
        const Rect& r = scene.rects[i];
        V3 a = r.right * r.half_width, b = r.up * r.half_height;
        for (V3 corner : {r.center - a - b, r.center + a - b, r.center + a + b, r.center - a + b}) {
          *v++ = corner.x, *v++ = corner.y, *v++ = corner.z;
        }
        unsigned k = 4 * i;
        unsigned tris[6] = {k, k + 1, k + 2, k, k + 2, k + 3};
        for (unsigned t : tris) *index++ = t;
      }
      rtcCommitGeometry(g);
      rect_geometry_ = rtcAttachGeometry(rtc_, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(rtc_);
  }

  ~Tracer() { rtcReleaseScene(rtc_); }

  // The colour seen along a camera ray, before clamping.
  Color radiance(V3 origin, V3 dir, Counters& counters) const {
    counters.primary++;
    return path(origin, dir, nullptr, counters);
  }

  // The colours seen along the camera rays of a tile of up to 8 pixels
  // (`valid[k]` -1 for a ray, 0 for none), their first hits found by one
  // rtcIntersect8, before clamping.
  void radiance8(const int* valid, const V3* dirs, Color* colors, Counters& counters) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit8 rh;
    for (int k = 0; k < 8; k++) {
      rh.ray.org_x[k] = 0, rh.ray.org_y[k] = 0, rh.ray.org_z[k] = 0;
      rh.ray.dir_x[k] = dirs[k].x, rh.ray.dir_y[k] = dirs[k].y, rh.ray.dir_z[k] = dirs[k].z;
      rh.ray.tnear[k] = 0;
      rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
      rh.ray.time[k] = 0;
      rh.ray.mask[k] = ~0u;
      rh.ray.id[k] = k;
      rh.ray.flags[k] = 0;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, rtc_, &context, &rh);
    for (int k = 0; k < 8; k++) {
      if (!valid[k]) continue;
      counters.primary++;
      First first{rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.primID[k]};
      colors[k] = path(V3{}, dirs[k], &first, counters);
    }
  }

 private:
  // A camera ray's first hit, found by a packet.
  struct First {
    float t;
    unsigned geom, prim;
  };

  // The colour of the path of a camera ray, its first hit found already
  // when `first` is given.
  Color path(V3 origin, V3 dir, const First* first, Counters& counters) const {
    Color color;
    double weight = 1;
    for (int depth = 0; depth <= MAX_DEPTH; depth++) {
      RTCRayHit rh;
      if (depth == 0 && first) {
        rh.ray.tfar = first->t;
        rh.hit.geomID = first->geom;
        rh.hit.primID = first->prim;
      } else {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        set_ray(rh.ray, origin, dir, std::numeric_limits<float>::infinity());
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(rtc_, &context, &rh);
      }
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      V3 along = origin + dir * rh.ray.tfar;
      V3 point, normal, center;
      const Material* material;
      double u = 0, v = 0;
      if (rh.hit.geomID == sphere_geometry_) {
        const Sphere& s = scene_.spheres[rh.hit.primID];
        V3 outward = normalize(along - s.center);
        point = s.center + outward * s.radius;
        normal = outward;
        center = s.center;
        material = &s.material;
        u = 0.5 + std::atan2(double(outward.z), double(outward.x)) / (2 * M_PI);
        v = 0.5 + std::asin(std::clamp(double(outward.y), -1.0, 1.0)) / M_PI;
      } else {
        const Rect& r = scene_.rects[rh.hit.primID / 2];
        V3 local = along - r.center;
        float x = dot(local, r.right), y = dot(local, r.up);
        point = r.center + r.right * x + r.up * y;
        normal = r.normal;
        center = r.center;
        material = &r.material;
        u = double(x) / double(r.half_width + r.half_width) + 0.5;
        v = double(y) / double(r.half_height + r.half_height) + 0.5;
      }
      if (dot(normal, dir) > 0) normal = normal * -1.0f;
      float scale = max_abs(point) + max_abs(center);
      Color albedo = material->texture >= 0 ? texel(scene_.textures[material->texture], u, v) : material->color;
      color = color + local(point, normal, scale, albedo, color, weight, counters) * weight;
      double k = material->reflectivity;
      if (k == 0 || depth == MAX_DEPTH || saturated(color)) break;
      weight *= k;
      origin = offset(point, normal, scale);
      dir = normalize(dir - normal * (2.0f * dot(dir, normal)));
      counters.reflection++;
    }
    return color;
  }

  static void set_ray(RTCRay& ray, V3 origin, V3 dir, float tfar) {
    ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
    ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
    ray.tnear = 0;
    ray.tfar = tfar;
    ray.time = 0;
    ray.mask = ~0u;
    ray.id = 0;
    ray.flags = 0;
  }

  // The hit point moved off its surface, as offset_origin in geometry.rs.
  static V3 offset(V3 point, V3 normal, float scale) {
    float step = OFFSET_ULPS * std::numeric_limits<float>::epsilon() *
                 std::max(scale, std::numeric_limits<float>::min());
    return point + normal * step;
  }

  static Color texel(const Texture& t, double u, double v) {
    // Truncation is the floor for values ≥ 0; negatives clamp to 0.
    int x = std::min(int(std::max(0.0, u * t.width)), t.width - 1);
    int y = std::min(int(std::max(0.0, (1 - v) * t.height)), t.height - 1);
    return t.texels[size_t(y) * t.width + x];
  }

  Color local(V3 point, V3 normal, float scale, Color albedo, Color color, double weight,
              Counters& counters) const {
    Color local = albedo * AMBIENT;
    for (const Light& light : scene_.lights) {
      Color contribution = albedo * light.color;
      V3 to_light = light.position - point;
      float length_ = length(to_light);
      if (length_ == 0) continue;
      double cos = dot(normal, to_light * (1.0f / length_));
      if (cos <= 0 || is_black(contribution) || saturated(color + local * weight)) continue;
      V3 origin = offset(point, normal, scale);
      V3 to = light.position - origin;
      float distance = length(to);
      if (distance == 0) continue;
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      RTCRay ray;
      set_ray(ray, origin, to * (1.0f / distance), distance * SHADOW_REACH);
      counters.shadow++;
      rtcOccluded1(rtc_, &context, &ray);
      if (ray.tfar >= 0) local = local + contribution * cos;
    }
    return local;
  }

  const Scene& scene_;
  RTCScene rtc_;
  unsigned sphere_geometry_ = RTC_INVALID_GEOMETRY_ID;
  unsigned rect_geometry_ = RTC_INVALID_GEOMETRY_ID;
};

unsigned char quantize(double c) {
  double x = std::clamp(c, 0.0, 1.0) * 255.0;
  return static_cast<unsigned char>(std::floor(x + 0.5));
}

void write_ppm(const std::string& path, int size, const std::vector<unsigned char>& rgb) {
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << size << " " << size << "\n255\n";
  out.write(reinterpret_cast<const char*>(rgb.data()), std::streamsize(rgb.size()));
  if (!out) fail("cannot write `" + path + "`");
}

// Largest and mean absolute difference from a PPM of the same size.
void compare(const std::string& path, int size, const std::vector<unsigned char>& rgb) {
  Texture other = read_ppm(path);
  if (other.width != size || other.height != size) {
    fail("`" + path + "` is not a " + std::to_string(size) + "² image");
  }
  int largest = 0;
  double sum = 0;
  for (size_t i = 0; i < rgb.size(); i++) {
    const Color& c = other.texels[i / 3];
    double value = i % 3 == 0 ? c.r : i % 3 == 1 ? c.g : c.b;
    int d = std::abs(int(std::lround(value * 255)) - int(rgb[i]));
    largest = std::max(largest, d);
    sum += d;
  }
  std::printf("diff %s %d %.4f\n", path.c_str(), largest, sum / double(rgb.size()));
}

}  // namespace

int main(int argc, char** argv) {
  bool packets = argc > 1 && std::strcmp(argv[1], "--packets") == 0;
  if (packets) argc--, argv++;
  if (argc < 3) fail("usage: harness [--packets] SCENE OUT.ppm [COMPARE.ppm...]");
  Scene scene = read_scene(argv[1]);
  RTCDevice device = rtcNewDevice("threads=1");
  if (!device) fail("cannot create an Embree device");

  using Clock = std::chrono::steady_clock;
  auto start = Clock::now();
  Tracer tracer(scene, device);
  auto built = Clock::now();
  int n = scene.resolution;
  std::vector<unsigned char> rgb(size_t(n) * n * 3);
  Counters counters;
  auto camera = [n](int i, int j) {
    return normalize(V3{float(-0.5 + (i + 0.5) / n), float(0.5 - (j + 0.5) / n), -1.0f});
  };
  auto put = [&rgb, n](int i, int j, Color c) {
    unsigned char* p = &rgb[(size_t(j) * n + i) * 3];
    p[0] = quantize(c.r), p[1] = quantize(c.g), p[2] = quantize(c.b);
  };
  if (packets) {
    // Tiles of 4×2 pixels, lane k at (i + k % 4, j + k / 4).
    for (int j = 0; j < n; j += 2) {
      for (int i = 0; i < n; i += 4) {
        alignas(32) int valid[8];
        V3 dirs[8];
        Color colors[8];
        for (int k = 0; k < 8; k++) {
          int x = i + k % 4, y = j + k / 4;
          valid[k] = x < n && y < n ? -1 : 0;
          dirs[k] = valid[k] ? camera(x, y) : V3{0, 0, -1};
        }
        tracer.radiance8(valid, dirs, colors, counters);
        for (int k = 0; k < 8; k++) {
          if (valid[k]) put(i + k % 4, j + k / 4, colors[k]);
        }
      }
    }
  } else {
    for (int j = 0; j < n; j++) {
      for (int i = 0; i < n; i++) put(i, j, tracer.radiance(V3{}, camera(i, j), counters));
    }
  }
  auto done = Clock::now();
  auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
  std::printf("primary_rays %llu\nshadow_rays %llu\nreflection_rays %llu\n", counters.primary, counters.shadow,
              counters.reflection);
  std::printf("build %.6f\ntrace %.6f\nseconds %.6f\n", seconds(built - start), seconds(done - built),
              seconds(done - start));
  write_ppm(argv[2], n, rgb);
  for (int k = 3; k < argc; k++) compare(argv[k], n, rgb);
  rtcReleaseDevice(device);
  return 0;
}
