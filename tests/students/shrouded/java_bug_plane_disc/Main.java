// HW4 ray tracer (Java).  Usage: java -cp . Main scene_description_file output_image
// Written from the HW4 handout only.  Output is always a binary PPM (P6, maxval 255).
import java.io.*;
import java.nio.charset.*;
import java.nio.file.*;
import java.util.*;
import java.util.regex.Pattern;

public class Main {

    // ---------------------------------------------------------------- vectors
    static final class V {
        final double x, y, z;
        V(double x, double y, double z) { this.x = x; this.y = y; this.z = z; }
        V add(V o) { return new V(x + o.x, y + o.y, z + o.z); }
        V sub(V o) { return new V(x - o.x, y - o.y, z - o.z); }
        V mul(double s) { return new V(x * s, y * s, z * s); }
        V mul(V o) { return new V(x * o.x, y * o.y, z * o.z); }
        double dot(V o) { return x * o.x + y * o.y + z * o.z; }
        V cross(V o) { return new V(y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x); }
        double len() { return Math.sqrt(dot(this)); }
        V norm() { double l = len(); return new V(x / l, y / l, z / l); }
    }

    static final V BLACK = new V(0, 0, 0);

    // ---------------------------------------------------------------- errors
    static final class SceneError extends Exception {
        SceneError(String m) { super(m); }
    }

    // ---------------------------------------------------------------- textures
    static final class Texture {
        int w, h;
        double[] px; // r,g,b in [0,1]
        V get(double u, double v) {
            u = u - Math.floor(u);
            v = v - Math.floor(v);
            int i = (int) (u * w); if (i >= w) i = w - 1; if (i < 0) i = 0;
            int j = (int) (v * h); if (j >= h) j = h - 1; if (j < 0) j = 0;
            int k = 3 * (j * w + i);
            return new V(px[k], px[k + 1], px[k + 2]);
        }
    }

    static final class PpmReader {
        final byte[] b; int p = 0;
        PpmReader(byte[] b) { this.b = b; }
        void skipWsAndComments() {
            while (p < b.length) {
                int c = b[p] & 0xff;
                if (c == '#') { while (p < b.length && b[p] != '\n' && b[p] != '\r') p++; }
                else if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == 0x0b || c == 0x0c) p++;
                else break;
            }
        }
        String token() {
            skipWsAndComments();
            int s = p;
            while (p < b.length) {
                int c = b[p] & 0xff;
                if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == 0x0b || c == 0x0c || c == '#') break;
                p++;
            }
            return new String(b, s, p - s, StandardCharsets.ISO_8859_1);
        }
        int integer(String what) throws SceneError {
            String t = token();
            if (!t.matches("[0-9]+")) throw new SceneError("bad " + what + " in texture header: '" + t + "'");
            try { return Integer.parseInt(t); } catch (NumberFormatException e) { throw new SceneError("bad " + what + " in texture"); }
        }
    }

    static Texture loadTexture(Path path) throws SceneError {
        byte[] data;
        try { data = Files.readAllBytes(path); }
        catch (IOException e) { throw new SceneError("cannot read texture file " + path); }
        PpmReader r = new PpmReader(data);
        String magic = r.token();
        if (!magic.equals("P6") && !magic.equals("P3")) throw new SceneError("texture " + path + " is not a P3/P6 PPM file");
        int w = r.integer("width"), h = r.integer("height"), max = r.integer("maxval");
        if (w <= 0 || h <= 0 || max <= 0 || max > 65535) throw new SceneError("bad texture header in " + path);
        Texture t = new Texture();
        t.w = w; t.h = h; t.px = new double[3 * w * h];
        int n = 3 * w * h;
        if (magic.equals("P6")) {
            r.p++; // single whitespace after maxval
            int bpc = max < 256 ? 1 : 2;
            if (r.p + (long) n * bpc > data.length) throw new SceneError("texture " + path + " is truncated");
            for (int i = 0; i < n; i++) {
                int v;
                if (bpc == 1) v = data[r.p + i] & 0xff;
                else v = ((data[r.p + 2 * i] & 0xff) << 8) | (data[r.p + 2 * i + 1] & 0xff);
                t.px[i] = Math.min(1.0, v / (double) max);
            }
        } else {
            for (int i = 0; i < n; i++) {
                String tok = r.token();
                if (tok.isEmpty()) throw new SceneError("texture " + path + " is truncated");
                if (!tok.matches("[0-9]+")) throw new SceneError("bad sample in texture " + path);
                t.px[i] = Math.min(1.0, Integer.parseInt(tok) / (double) max);
            }
        }
        return t;
    }

    // ---------------------------------------------------------------- scene
    static abstract class Obj {
        V center = new V(0, 0, 0);
        V color = new V(1, 1, 1);
        double reflectivity = 0;
        Texture texture;
        abstract double hit(V o, V d, double tmin);      // returns t or -1
        abstract V normal(V p);
        abstract V texColor(V p);
    }

    static final class Sphere extends Obj {
        double r = 1;
        double hit(V o, V d, double tmin) {
            V oc = o.sub(center);
            double a = d.dot(d);
            double b = 2 * d.dot(oc);
            double c = oc.dot(oc) - r * r;
            double disc = b * b - 4 * a * c;
            if (disc < 0) return -1;
            double sq = Math.sqrt(disc);
            double t1 = (-b - sq) / (2 * a);
            if (t1 > tmin) return t1;
            double t2 = (-b + sq) / (2 * a);
            if (t2 > tmin) return t2;
            return -1;
        }
        V normal(V p) { return p.sub(center).norm(); }
        V texColor(V p) {
            V n = p.sub(center).norm();
            double u = 0.5 + Math.atan2(n.x, n.z) / (2 * Math.PI);
            double v = Math.acos(Math.max(-1, Math.min(1, n.y))) / Math.PI;
            return texture.get(u, v);
        }
    }

    static final class Plane extends Obj {
        double w = 1, h = 1;           // "dimension w h": w across, h along headup
        V n = new V(0, 0, 1);
        V headup = new V(0, 1, 0);
        V up, right;                   // orthonormal frame in the plane
        void setup() {
            n = n.norm();
            V u = headup.sub(n.mul(headup.dot(n)));
            if (u.len() < 1e-9) {
                V alt = Math.abs(n.y) < 0.9 ? new V(0, 1, 0) : new V(0, 0, -1);
                u = alt.sub(n.mul(alt.dot(n)));
            }
            up = u.norm();
            right = up.cross(n).norm();
        }
        double hit(V o, V d, double tmin) {
            double den = n.dot(d);
            if (Math.abs(den) < 1e-12) return -1;
            double t = n.dot(center.sub(o)) / den;
            if (t <= tmin) return -1;
            V q = o.add(d.mul(t)).sub(center);
            if (q.len() > w / 2) return -1;
            return t;
        }
        V normal(V p) { return n; }
        V texColor(V p) {
            V q = p.sub(center);
            double u = q.dot(right) / w + 0.5;
            double v = 0.5 - q.dot(up) / h;
            return texture.get(u, v);
        }
    }

    static final class Light {
        V pos = new V(0, 0, 0);
        V color = new V(1, 1, 1);
    }

    static int res = -1;
    static final List<Obj> objs = new ArrayList<>();
    static final List<Light> lights = new ArrayList<>();

    // ---------------------------------------------------------------- parsing
    static final Pattern NUM = Pattern.compile("[+-]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][+-]?[0-9]+)?");

    static boolean isSep(int c) {
        return Character.isWhitespace(c) || Character.isSpaceChar(c) || c == 0x85 || c == 0xFEFF || c == 0x200B;
    }

    static List<String> tokenize(String s) {
        List<String> out = new ArrayList<>();
        StringBuilder cur = new StringBuilder();
        for (int i = 0; i < s.length(); ) {
            int c = s.codePointAt(i);
            i += Character.charCount(c);
            if (isSep(c)) {
                if (cur.length() > 0) { out.add(cur.toString()); cur.setLength(0); }
            } else cur.appendCodePoint(c);
        }
        if (cur.length() > 0) out.add(cur.toString());
        return out;
    }

    static List<String> toks; static int tp;

    static double num(String what) throws SceneError {
        if (tp >= toks.size()) throw new SceneError("missing number for " + what);
        String t = toks.get(tp++);
        if (!NUM.matcher(t).matches()) throw new SceneError("expected a number for " + what + ", got '" + t + "'");
        double v = Double.parseDouble(t);
        if (Double.isNaN(v) || Double.isInfinite(v)) throw new SceneError("number out of range: " + t);
        return v;
    }

    static V vec(String what) throws SceneError { return new V(num(what), num(what), num(what)); }

    static void parse(Path scene) throws SceneError {
        byte[] raw;
        try { raw = Files.readAllBytes(scene); }
        catch (IOException e) { throw new SceneError("cannot read scene file " + scene); }
        String text = new String(raw, StandardCharsets.UTF_8);
        Path dir = scene.toAbsolutePath().getParent();
        toks = tokenize(text); tp = 0;
        Obj cur = null; Light curL = null;
        while (tp < toks.size()) {
            String k = toks.get(tp++);
            switch (k) {
                case "camera": {
                    if (res > 0) throw new SceneError("more than one camera");
                    double v = num("camera");
                    if (v != Math.floor(v) || v < 1 || v > 20000) throw new SceneError("bad camera resolution " + v);
                    res = (int) v;
                    cur = null; curL = null;
                    break;
                }
                case "sphere": cur = new Sphere(); objs.add(cur); curL = null; break;
                case "plane": cur = new Plane(); objs.add(cur); curL = null; break;
                case "light": curL = new Light(); lights.add(curL); cur = null; break;
                case "dimension":
                    if (cur instanceof Sphere) {
                        double r = num("dimension");
                        if (r <= 0) throw new SceneError("sphere dimension must be positive");
                        ((Sphere) cur).r = r;
                    } else if (cur instanceof Plane) {
                        double a = num("dimension"), b = num("dimension");
                        if (a <= 0 || b <= 0) throw new SceneError("plane dimensions must be positive");
                        ((Plane) cur).w = a; ((Plane) cur).h = b;
                    } else throw new SceneError("'dimension' outside an object");
                    break;
                case "center":
                    if (cur == null) throw new SceneError("'center' outside an object");
                    cur.center = vec("center"); break;
                case "color":
                    if (cur != null) cur.color = vec("color");
                    else if (curL != null) curL.color = vec("color");
                    else throw new SceneError("'color' outside an object or light");
                    break;
                case "reflectivity":
                    if (cur == null) throw new SceneError("'reflectivity' outside an object");
                    cur.reflectivity = num("reflectivity"); break;
                case "texture": {
                    if (cur == null) throw new SceneError("'texture' outside an object");
                    if (tp >= toks.size()) throw new SceneError("missing texture file name");
                    String f = toks.get(tp++);
                    Path p = Paths.get(f);
                    if (!p.isAbsolute() && dir != null) p = dir.resolve(p);
                    cur.texture = loadTexture(p);
                    break;
                }
                case "normal":
                    if (!(cur instanceof Plane)) throw new SceneError("'normal' outside a plane");
                    ((Plane) cur).n = vec("normal"); break;
                case "headup":
                    if (!(cur instanceof Plane)) throw new SceneError("'headup' outside a plane");
                    ((Plane) cur).headup = vec("headup"); break;
                case "location":
                    if (curL == null) throw new SceneError("'location' outside a light");
                    curL.pos = vec("location"); break;
                default:
                    throw new SceneError("unknown keyword '" + k + "'");
            }
        }
        if (res <= 0) throw new SceneError("no camera line in scene");
        for (Obj o : objs) if (o instanceof Plane) {
            Plane pl = (Plane) o;
            if (pl.n.len() < 1e-12) throw new SceneError("plane normal is zero");
            pl.setup();
        }
    }

    // ---------------------------------------------------------------- tracing
    static final double KA = 0.1, KS = 0.3, SHININESS = 20, OFFSET = 1e-4;
    static final int MAX_DEPTH = 5;

    static Obj hitObj; static double hitT;

    static boolean nearest(V o, V d, double tmin) {
        hitObj = null; hitT = Double.MAX_VALUE;
        for (Obj ob : objs) {
            double t = ob.hit(o, d, tmin);
            if (t > tmin && t < hitT) { hitT = t; hitObj = ob; }
        }
        return hitObj != null;
    }

    static boolean blocked(V o, V d, double dist) {
        for (Obj ob : objs) {
            double t = ob.hit(o, d, 1e-9);
            if (t > 1e-9 && t < dist) return true;
        }
        return false;
    }

    static V trace(V o, V d, int depth) {
        if (!nearest(o, d, 1e-9)) return BLACK;
        Obj ob = hitObj;
        V p = o.add(d.mul(hitT));
        V n = ob.normal(p);
        if (n.dot(d) > 0) n = n.mul(-1);
        V base = ob.texture != null ? ob.texColor(p) : ob.color;
        V col = base.mul(KA);
        V view = d.mul(-1);
        V po = p.add(n.mul(OFFSET));
        for (Light l : lights) {
            V L = l.pos.sub(p);
            double dist = L.len();
            if (dist < 1e-12) continue;
            L = L.mul(1 / dist);
            double ndl = n.dot(L);
            if (ndl <= 0) continue;
            if (blocked(po, L, dist)) continue;
            col = col.add(base.mul(l.color).mul(ndl));
            V r = n.mul(2 * ndl).sub(L);
            double rv = r.dot(view);
            if (rv > 0) col = col.add(l.color.mul(KS * Math.pow(rv, SHININESS)));
        }
        if (ob.reflectivity > 0 && depth < MAX_DEPTH) {
            V rd = d.sub(n.mul(2 * d.dot(n))).norm();
            col = col.add(trace(po, rd, depth + 1).mul(ob.reflectivity));
        }
        return col;
    }

    static int to8(double c) {
        if (!(c > 0)) return 0;
        if (c >= 1) return 255;
        return (int) (c * 255 + 0.5);
    }

    public static void main(String[] args) {
        if (args.length != 2) {
            System.err.println("usage: java Main scene_description_file output_image");
            System.exit(1);
        }
        try {
            parse(Paths.get(args[0]));
        } catch (SceneError e) {
            System.err.println("error: " + e.getMessage());
            System.exit(1);
        }
        int n = res;
        byte[] header = ("P6\n" + n + " " + n + "\n255\n").getBytes(StandardCharsets.US_ASCII);
        byte[] img = new byte[header.length + 3 * n * n];
        System.arraycopy(header, 0, img, 0, header.length);
        int k = header.length;
        for (int j = 0; j < n; j++) {
            for (int i = 0; i < n; i++) {
                double x = -0.5 + (i + 0.5) / n;
                double y = 0.5 - (j + 0.5) / n;
                V d = new V(x, y, -1).norm();
                V c = trace(new V(0, 0, 0), d, 0);
                img[k++] = (byte) to8(c.x);
                img[k++] = (byte) to8(c.y);
                img[k++] = (byte) to8(c.z);
            }
        }
        try (OutputStream os = new FileOutputStream(args[1])) {
            os.write(img);
        } catch (IOException e) {
            System.err.println("error: cannot write " + args[1]);
            System.exit(1);
        }
    }
}
