import java.awt.image.BufferedImage;
import java.io.*;
import java.nio.file.Files;
import java.util.ArrayList;
import java.util.List;
import javax.imageio.ImageIO;

/**
 * CS180 HW4 - simple recursive ray tracer.
 * Usage: java Main scene_file output_image
 * Writes a plain (P3) ppm, or a png if the output name ends in .png
 */
public class Main {

    static final int MAX_DEPTH = 4;
    static final double AMBIENT = 0.1;
    static final double OFFSET = 1e-3;   // push secondary rays off the surface
    static final double T_MIN = 1e-6;

    // ------------------------------------------------------------ vector
    static class V3 {
        final double x, y, z;
        V3(double x, double y, double z) { this.x = x; this.y = y; this.z = z; }
        V3 plus(V3 o) { return new V3(x + o.x, y + o.y, z + o.z); }
        V3 minus(V3 o) { return new V3(x - o.x, y - o.y, z - o.z); }
        V3 times(double s) { return new V3(x * s, y * s, z * s); }
        V3 times(V3 o) { return new V3(x * o.x, y * o.y, z * o.z); }
        double dot(V3 o) { return x * o.x + y * o.y + z * o.z; }
        V3 cross(V3 o) { return new V3(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x); }
        double length() { return Math.sqrt(dot(this)); }
        V3 unit() { double l = length(); return l == 0 ? this : times(1.0 / l); }
    }

    static final V3 BLACK = new V3(0, 0, 0);

    // ------------------------------------------------------------ texture
    static class Texture {
        int w, h;
        double[] rgb;

        Texture(File f) throws IOException {
            byte[] b = Files.readAllBytes(f.toPath());
            int[] p = {0};
            String magic = next(b, p);
            if (!magic.equals("P3") && !magic.equals("P6"))
                throw new IOException(f + ": not a P3/P6 ppm file");
            w = Integer.parseInt(next(b, p));
            h = Integer.parseInt(next(b, p));
            int max = Integer.parseInt(next(b, p));
            if (w <= 0 || h <= 0 || max <= 0 || max > 65535) throw new IOException(f + ": bad ppm header");
            rgb = new double[3 * w * h];
            if (magic.equals("P3")) {
                for (int i = 0; i < rgb.length; i++) rgb[i] = Integer.parseInt(next(b, p)) / (double) max;
            } else {
                int at = p[0] + 1;
                int bytes = max > 255 ? 2 : 1;
                if (b.length - at < rgb.length * bytes) throw new IOException(f + ": ppm data too short");
                for (int i = 0; i < rgb.length; i++) {
                    int v = b[at++] & 0xff;
                    if (bytes == 2) v = (v << 8) | (b[at++] & 0xff);
                    rgb[i] = v / (double) max;
                }
            }
        }

        // header / P3 token reader, skips # comments
        static String next(byte[] b, int[] p) throws IOException {
            int i = p[0];
            while (i < b.length) {
                if (b[i] == '#') { while (i < b.length && b[i] != '\n') i++; }
                else if (Character.isWhitespace(b[i])) i++;
                else break;
            }
            int s = i;
            while (i < b.length && !Character.isWhitespace(b[i]) && b[i] != '#') i++;
            if (s == i) throw new IOException("unexpected end of ppm file");
            p[0] = i;
            return new String(b, s, i - s);
        }

        V3 texel(int x, int y) {
            int k = 3 * (y * w + x);
            return new V3(rgb[k], rgb[k + 1], rgb[k + 2]);
        }

        // u,v in [0,1], v = 0 is the first (top) row of the file
        V3 sample(double u, double v) {
            u -= Math.floor(u);
            int x = Math.min(w - 1, Math.max(0, (int) (u * w)));
            int y = Math.min(h - 1, Math.max(0, (int) (v * h)));
            return texel(x, y);
        }
    }

    // ------------------------------------------------------------ objects
    static abstract class Shape {
        V3 center = BLACK;
        V3 color = new V3(1, 1, 1);
        double reflectivity = 0;
        Texture texture;

        abstract double hit(V3 o, V3 d);      // distance or -1
        abstract V3 normal(V3 p);
        abstract double[] uv(V3 p);

        V3 colorAt(V3 p) {
            if (texture == null) return color;
            double[] t = uv(p);
            return texture.sample(t[0], t[1]);
        }
        void prepare() {}
    }

    static class Sphere extends Shape {
        double r = 1;

        double hit(V3 o, V3 d) {            // d is unit length
            V3 oc = o.minus(center);
            double b = oc.dot(d);
            double c = oc.dot(oc) - r * r;
            double disc = b * b - c;
            if (disc < 0) return -1;
            double s = Math.sqrt(disc);
            double t = -b - s;
            if (t > T_MIN) return t;
            t = -b + s;
            return t > T_MIN ? t : -1;
        }

        V3 normal(V3 p) { return p.minus(center).unit(); }

        double[] uv(V3 p) {
            V3 n = p.minus(center).unit();
            double u = 0.5 + Math.atan2(n.x, n.z) / (2 * Math.PI);
            double v = 0.5 - Math.asin(Math.max(-1, Math.min(1, n.y))) / Math.PI;
            return new double[] {u, v};
        }
    }

    static class Plane extends Shape {
        double width = 1, height = 1;
        V3 n = new V3(0, 1, 0), headup = new V3(0, 0, -1);
        V3 up, right;

        void prepare() {
            n = n.unit();
            if (n.length() == 0) n = new V3(0, 1, 0);
            up = headup.minus(n.times(headup.dot(n)));
            if (up.length() < 1e-9) {
                V3 a = Math.abs(n.x) < 0.9 ? new V3(1, 0, 0) : new V3(0, 0, 1);
                up = a.minus(n.times(a.dot(n)));
            }
            up = up.unit();
            right = up.cross(n);
        }

        double hit(V3 o, V3 d) {
            double dn = d.dot(n);
            if (Math.abs(dn) < 1e-12) return -1;
            double t = center.minus(o).dot(n) / dn;
            if (t <= T_MIN) return -1;
            V3 q = o.plus(d.times(t)).minus(center);
            if (Math.abs(q.dot(right)) > width / 2 || Math.abs(q.dot(up)) > height / 2) return -1;
            return t;
        }

        V3 normal(V3 p) { return n; }

        double[] uv(V3 p) {
            V3 q = p.minus(center);
            return new double[] {q.dot(right) / width + 0.5, 0.5 - q.dot(up) / height};
        }
    }

    static class Light {
        V3 pos = BLACK;
        V3 color = new V3(1, 1, 1);
    }

    // ------------------------------------------------------------ scene
    static int res = 0;
    static List<Shape> shapes = new ArrayList<>();
    static List<Light> lights = new ArrayList<>();

    static V3 vec(String[] t, int line) {
        if (t.length < 4) throw new IllegalArgumentException("line " + line + ": " + t[0] + " needs 3 numbers");
        return new V3(num(t[1], line), num(t[2], line), num(t[3], line));
    }

    static double num(String s, int line) {
        try {
            return Double.parseDouble(s);
        } catch (NumberFormatException e) {
            throw new IllegalArgumentException("line " + line + ": bad number '" + s + "'");
        }
    }

    static void add(Object section) {
        if (section instanceof Shape) {
            ((Shape) section).prepare();
            shapes.add((Shape) section);
        } else if (section instanceof Light) {
            lights.add((Light) section);
        }
    }

    static void readScene(File file) throws IOException {
        File dir = file.getAbsoluteFile().getParentFile();
        Object cur = null;   // section being read, added when the next one starts
        int lineNo = 0;
        try (BufferedReader in = new BufferedReader(new FileReader(file))) {
            String line;
            while ((line = in.readLine()) != null) {
                lineNo++;
                int hash = line.indexOf('#');
                if (hash >= 0) line = line.substring(0, hash);
                line = line.trim();
                if (line.isEmpty()) continue;
                String[] t = line.split("\\s+");
                String key = t[0].toLowerCase();

                if (key.equals("camera")) {
                    if (t.length < 2) throw new IllegalArgumentException("line " + lineNo + ": camera needs a size");
                    res = (int) num(t[1], lineNo);
                    if (res <= 0) throw new IllegalArgumentException("line " + lineNo + ": bad camera size");
                } else if (key.equals("sphere") || key.equals("plane") || key.equals("light")) {
                    add(cur);
                    cur = key.equals("sphere") ? new Sphere() : key.equals("plane") ? new Plane() : new Light();
                } else if (cur instanceof Light) {
                    Light l = (Light) cur;
                    if (key.equals("location") || key.equals("center")) l.pos = vec(t, lineNo);
                    else if (key.equals("color")) l.color = vec(t, lineNo);
                    else System.err.println("warning: line " + lineNo + ": ignoring '" + t[0] + "'");
                } else if (cur instanceof Shape) {
                    Shape s = (Shape) cur;
                    switch (key) {
                        case "center": s.center = vec(t, lineNo); break;
                        case "color": s.color = vec(t, lineNo); break;
                        case "reflectivity":
                            if (t.length < 2) throw new IllegalArgumentException("line " + lineNo + ": reflectivity needs a value");
                            s.reflectivity = num(t[1], lineNo);
                            break;
                        case "texture":
                            if (t.length < 2) throw new IllegalArgumentException("line " + lineNo + ": texture needs a file");
                            File tf = new File(t[1]);
                            if (!tf.isAbsolute()) tf = new File(dir, t[1]);
                            s.texture = new Texture(tf);
                            break;
                        case "dimension":
                            if (t.length < 2) throw new IllegalArgumentException("line " + lineNo + ": dimension needs a value");
                            if (s instanceof Sphere) ((Sphere) s).r = num(t[1], lineNo);
                            else {
                                Plane p = (Plane) s;
                                p.width = num(t[1], lineNo);
                                p.height = t.length > 2 ? num(t[2], lineNo) : p.width;
                            }
                            break;
                        case "normal":
                            if (s instanceof Plane) ((Plane) s).n = vec(t, lineNo);
                            break;
                        case "headup":
                            if (s instanceof Plane) ((Plane) s).headup = vec(t, lineNo);
                            break;
                        default:
                            System.err.println("warning: line " + lineNo + ": ignoring '" + t[0] + "'");
                    }
                } else {
                    throw new IllegalArgumentException("line " + lineNo + ": '" + t[0] + "' outside of a section");
                }
            }
        }
        add(cur);
        if (res <= 0) throw new IllegalArgumentException("scene has no camera line");
    }

    // ------------------------------------------------------------ tracing
    static Shape hitShape;
    static double hitT;

    static boolean nearest(V3 o, V3 d) {
        hitShape = null;
        hitT = Double.MAX_VALUE;
        for (Shape s : shapes) {
            double t = s.hit(o, d);
            if (t > 0 && t < hitT) { hitT = t; hitShape = s; }
        }
        return hitShape != null;
    }

    static boolean blocked(V3 from, V3 dir, double maxDist) {
        for (Shape s : shapes) {
            double t = s.hit(from, dir);
            if (t > 0 && t < maxDist) return true;
        }
        return false;
    }

    static V3 trace(V3 o, V3 d, int depth) {
        if (!nearest(o, d)) return BLACK;
        Shape s = hitShape;
        V3 p = o.plus(d.times(hitT));
        V3 n = s.normal(p);
        if (n.dot(d) > 0) n = n.times(-1);
        V3 base = s.colorAt(p);
        V3 start = p.plus(n.times(OFFSET));

        // Phong: ambient + diffuse (kd = object colour)
        V3 c = base.times(AMBIENT);
        for (Light l : lights) {
            V3 toLight = l.pos.minus(p);
            double dist = toLight.length();
            V3 L = toLight.times(1.0 / dist);
            double cos = n.dot(L);
            if (cos <= 0) continue;
            if (blocked(start, L, dist)) continue;     // shadow ray
            c = c.plus(base.times(l.color).times(cos));
        }

        // reflection: += reflected colour * reflectivity
        if (s.reflectivity > 0 && depth < MAX_DEPTH) {
            V3 r = d.minus(n.times(2 * d.dot(n))).unit();
            c = c.plus(trace(start, r, depth + 1).times(s.reflectivity));
        }
        return c;
    }

    static int toByte(double v) {
        v = Math.max(0, Math.min(1, v));
        return (int) (v * 255 + 0.5);
    }

    static void write(int[][] img, String out) throws IOException {
        int n = img.length;
        if (out.toLowerCase().endsWith(".png")) {
            BufferedImage bi = new BufferedImage(n, n, BufferedImage.TYPE_INT_RGB);
            for (int y = 0; y < n; y++)
                for (int x = 0; x < n; x++) bi.setRGB(x, y, img[y][x]);
            ImageIO.write(bi, "png", new File(out));
            return;
        }
        try (PrintWriter w = new PrintWriter(new BufferedWriter(new FileWriter(out)))) {
            w.print("P3\n" + n + " " + n + "\n255\n");
            for (int y = 0; y < n; y++) {
                StringBuilder sb = new StringBuilder();
                for (int x = 0; x < n; x++) {
                    int rgb = img[y][x];
                    sb.append((rgb >> 16) & 255).append(' ').append((rgb >> 8) & 255).append(' ').append(rgb & 255).append(' ');
                }
                w.println(sb.toString().trim());
            }
            if (w.checkError()) throw new IOException("write failed: " + out);
        }
    }

    public static void main(String[] args) {
        if (args.length != 2) {
            System.err.println("usage: java Main scene_description_file output_image");
            System.exit(2);
        }
        try {
            readScene(new File(args[0]));
        } catch (IOException | RuntimeException e) {
            System.err.println("cannot read scene " + args[0] + ": " + e.getMessage());
            System.exit(1);
        }

        int n = res;
        int[][] img = new int[n][n];
        V3 eye = new V3(0, 0, 0);
        for (int row = 0; row < n; row++) {
            for (int col = 0; col < n; col++) {
                double px = (col + 0.5) / n - 0.5;    // pixel centre, image plane at z = -1
                double py = 0.5 - (row + 0.5) / n;
                V3 c = trace(eye, new V3(px, py, -1).unit(), 0);
                img[row][col] = (toByte(c.x) << 16) | (toByte(c.y) << 8) | toByte(c.z);
            }
        }
        try {
            write(img, args[1]);
        } catch (IOException e) {
            System.err.println("cannot write image: " + e.getMessage());
            System.exit(1);
        }
    }
}
