import java.io.*;
import java.nio.file.*;
import java.util.*;

/**
 * HW4 ray tracer.  Usage: java Main scene.txt out.ppm
 * Writes a binary PPM (P6), camera N x N.
 */
public class Main {
    static final int MAX_DEPTH = 6;
    static final double KA = 0.1;

    // ------------------------------------------------------------ vectors
    static final class Vec {
        final double x, y, z;
        Vec(double x, double y, double z) { this.x = x; this.y = y; this.z = z; }
        Vec plus(Vec o) { return new Vec(x + o.x, y + o.y, z + o.z); }
        Vec minus(Vec o) { return new Vec(x - o.x, y - o.y, z - o.z); }
        Vec times(double s) { return new Vec(x * s, y * s, z * s); }
        Vec times(Vec o) { return new Vec(x * o.x, y * o.y, z * o.z); }
        double dot(Vec o) { return x * o.x + y * o.y + z * o.z; }
        Vec cross(Vec o) { return new Vec(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x); }
        double length() { return Math.sqrt(dot(this)); }
        Vec unit() { double l = length(); return l == 0 ? this : times(1 / l); }
    }

    static final Vec BLACK = new Vec(0, 0, 0);

    // ------------------------------------------------------------ textures
    static final class Texture {
        int w, h;
        double[] rgb;

        Vec at(double u, double v) {   // u to the right, v down from the top row, both in [0,1]
            int i = (int) (u * w), j = (int) (v * h);
            i = Math.max(0, Math.min(w - 1, i));
            j = Math.max(0, Math.min(h - 1, j));
            int k = 3 * (j * w + i);
            return new Vec(rgb[k], rgb[k + 1], rgb[k + 2]);
        }

        static Texture load(Path p) throws IOException {
            byte[] b = Files.readAllBytes(p);
            int[] pos = {0};
            String magic = token(b, pos);
            int w = Integer.parseInt(token(b, pos));
            int h = Integer.parseInt(token(b, pos));
            int max = Integer.parseInt(token(b, pos));
            Texture t = new Texture();
            t.w = w; t.h = h; t.rgb = new double[w * h * 3];
            if (magic.equals("P6")) {
                int q = pos[0] + 1;
                for (int i = 0; i < w * h * 3; i++) {
                    int v;
                    if (max < 256) v = b[q++] & 0xff;
                    else { v = ((b[q] & 0xff) << 8) | (b[q + 1] & 0xff); q += 2; }
                    t.rgb[i] = (double) v / max;
                }
            } else if (magic.equals("P3")) {
                for (int i = 0; i < w * h * 3; i++) t.rgb[i] = Integer.parseInt(token(b, pos)) / (double) max;
            } else {
                throw new IOException(p + " is not a PPM");
            }
            return t;
        }

        private static String token(byte[] b, int[] pos) {
            int i = pos[0];
            while (true) {
                while (i < b.length && Character.isWhitespace(b[i])) i++;
                if (i < b.length && b[i] == '#') { while (i < b.length && b[i] != '\n') i++; continue; }
                break;
            }
            int s = i;
            while (i < b.length && !Character.isWhitespace(b[i])) i++;
            pos[0] = i;
            return new String(b, s, i - s);
        }
    }

    // ------------------------------------------------------------ objects
    static abstract class Shape {
        Vec center = BLACK, color = new Vec(1, 1, 1);
        double reflectivity = 0;
        Texture texture;
        double[] dimension;

        abstract double intersect(Vec e, Vec d, double tmin);   // smallest t > tmin, or -1
        abstract Vec normalAt(Vec p);
        abstract Vec textureColor(Vec p);

        Vec colorAt(Vec p) { return texture == null ? color : textureColor(p); }
        void prepare() { }
    }

    static final class Sphere extends Shape {
        double r;

        void prepare() { r = dimension[0]; }

        double intersect(Vec e, Vec d, double tmin) {
            Vec ec = e.minus(center);
            double a = d.dot(d);
            double b = 2 * d.dot(ec);
            double c = ec.dot(ec) - r * r;
            double disc = b * b - 4 * a * c;
            if (disc < 0) return -1;
            double sq = Math.sqrt(disc);
            double t1 = (-b - sq) / (2 * a);
            double t2 = (-b + sq) / (2 * a);
            if (t1 > tmin) return t1;
            if (t2 > tmin) return t2;
            return -1;
        }

        Vec normalAt(Vec p) { return p.minus(center).times(1 / r); }

        Vec textureColor(Vec p) {
            Vec q = p.minus(center).times(1 / r);
            double u = 0.5 + Math.atan2(q.z, q.x) / (2 * Math.PI);
            double v = Math.acos(Math.max(-1, Math.min(1, q.y))) / Math.PI;
            return texture.at(u, v);
        }
    }

    static final class Plane extends Shape {
        Vec normal = new Vec(0, 0, 1), headup = new Vec(0, 1, 0);
        Vec n, up, right;
        double width, height;

        void prepare() {
            width = dimension[0];
            height = dimension[1];
            n = normal.unit();
            up = headup.minus(n.times(headup.dot(n))).unit();
            right = up.cross(n);
        }

        double intersect(Vec e, Vec d, double tmin) {
            double denom = n.dot(d);
            if (denom == 0) return -1;
            double dconst = -n.dot(center);           // ax + by + cz + d = 0
            double t = -(n.dot(e) + dconst) / denom;
            if (t <= tmin) return -1;
            Vec q = e.plus(d.times(t)).minus(center);
            if (Math.abs(q.dot(right)) > width / 2 || Math.abs(q.dot(up)) > height / 2) return -1;
            return t;
        }

        Vec normalAt(Vec p) { return n; }

        Vec textureColor(Vec p) {
            Vec q = p.minus(center);
            double u = q.dot(right) / width + 0.5;
            double v = 0.5 - q.dot(up) / height;
            return texture.at(u, v);
        }
    }

    static final class Light {
        Vec location = BLACK, color = new Vec(1, 1, 1);
    }

    // ------------------------------------------------------------ scene
    int size;
    List<Shape> shapes = new ArrayList<>();
    List<Light> lights = new ArrayList<>();

    static Vec vec(String[] w) {
        return new Vec(Double.parseDouble(w[1]), Double.parseDouble(w[2]), Double.parseDouble(w[3]));
    }

    void load(Path file) throws IOException {
        Object current = null;
        for (String raw : Files.readAllLines(file)) {
            int hash = raw.indexOf('#');
            String line = (hash >= 0 ? raw.substring(0, hash) : raw).trim();
            if (line.isEmpty()) continue;
            String[] w = line.split("\\s+");
            switch (w[0]) {
                case "camera": size = (int) Double.parseDouble(w[1]); current = null; break;
                case "sphere": current = new Sphere(); shapes.add((Shape) current); break;
                case "plane": current = new Plane(); shapes.add((Shape) current); break;
                case "light": current = new Light(); lights.add((Light) current); break;
                default:
                    if (current instanceof Light) {
                        Light l = (Light) current;
                        if (w[0].equals("location")) l.location = vec(w);
                        else if (w[0].equals("color")) l.color = vec(w);
                    } else if (current instanceof Shape) {
                        Shape s = (Shape) current;
                        switch (w[0]) {
                            case "dimension":
                                s.dimension = new double[w.length - 1];
                                for (int i = 1; i < w.length; i++) s.dimension[i - 1] = Double.parseDouble(w[i]);
                                break;
                            case "center": s.center = vec(w); break;
                            case "color": s.color = vec(w); break;
                            case "reflectivity": s.reflectivity = Double.parseDouble(w[1]); break;
                            case "texture": {
                                Path dir = file.toAbsolutePath().getParent();
                                s.texture = Texture.load(dir.resolve(w[1]));
                                break;
                            }
                            case "normal": ((Plane) s).normal = vec(w); break;
                            case "headup": ((Plane) s).headup = vec(w); break;
                            default: System.err.println("unknown attribute " + w[0]);
                        }
                    }
            }
        }
        for (Shape s : shapes) s.prepare();
    }

    // ------------------------------------------------------------ tracing
    static double eps(Vec p) { return 1e-7 * (1 + p.length()); }

    Shape hitShape;
    double hitT;

    boolean closest(Vec e, Vec d, double tmin) {
        hitShape = null;
        hitT = Double.POSITIVE_INFINITY;
        for (Shape s : shapes) {
            double t = s.intersect(e, d, tmin);
            if (t > 0 && t < hitT) { hitT = t; hitShape = s; }
        }
        return hitShape != null;
    }

    boolean shadowed(Vec p, Vec lightPos) {
        Vec toLight = lightPos.minus(p);          // t = 1 is the light
        for (Shape s : shapes) {
            double t = s.intersect(p, toLight, 1e-6);
            if (t > 0 && t < 1 - 1e-6) return true;
        }
        return false;
    }

    Vec trace(Vec e, Vec d, int depth) {
        if (!closest(e, d, eps(e) / d.length())) return BLACK;
        Shape s = hitShape;
        Vec p = e.plus(d.times(hitT));
        Vec n = s.normalAt(p).unit();
        Vec u = d.unit();
        if (n.dot(u) > 0) n = n.times(-1);      // back of a plane, inside of a sphere

        Vec base = s.colorAt(p);
        Vec color = base.times(KA);
        for (Light l : lights) {
            Vec L = l.location.minus(p);
            if (L.length() == 0) continue;
            double cos = n.dot(L.unit());
            if (cos <= 0 || shadowed(p, l.location)) continue;
            color = color.plus(base.times(l.color).times(cos));
        }
        if (s.reflectivity > 0 && depth < MAX_DEPTH) {
            Vec r = u.plus(n.times(2 * u.dot(n)));   // r = d + 2(d.n)n
            color = color.plus(trace(p, r, depth + 1).times(s.reflectivity));
        }
        return color;
    }

    static int clamp(double c) {
        int v = (int) (c * 255);
        return v < 0 ? 0 : Math.min(255, v);
    }

    void render(String out) throws IOException {
        int n = size;
        byte[] img = new byte[n * n * 3];
        Vec eye = new Vec(0, 0, 0);
        for (int row = 0; row < n; row++) {
            for (int col = 0; col < n; col++) {
                double x = -0.5 + (col + 0.5) / n;
                double y = 0.5 - (row + 0.5) / n;
                Vec c = trace(eye, new Vec(x, y, -1), 0);   // s - e with e = origin
                int k = 3 * (row * n + col);
                img[k] = (byte) clamp(c.x);
                img[k + 1] = (byte) clamp(c.y);
                img[k + 2] = (byte) clamp(c.z);
            }
        }
        try (OutputStream os = new BufferedOutputStream(new FileOutputStream(out))) {
            os.write(("P6\n" + n + " " + n + "\n255\n").getBytes());
            os.write(img);
        }
    }

    public static void main(String[] args) throws IOException {
        if (args.length < 2) {
            System.err.println("usage: java Main scene.txt out.ppm");
            System.exit(1);
        }
        Main m = new Main();
        m.load(Paths.get(args[0]));
        m.render(args[1]);
    }
}
