// Convex polyhedra in f32: quaternion helpers, the shape table (shapes.rs) and
// the narrow phase of tumble-geom ported to WGSL: polyhedron–polyhedron
// (separating axes: face normals both ways and the edge pairs that form faces of
// the Minkowski difference, minimum penetration, the incident face clipped by the
// reference face, at most four points), sphere–polyhedron, and a polyhedron
// against a plane, a quad and a cylinder (drum shell inside, pipe outside).
// Lifters (prisms) go through polyhedron–polyhedron as table shapes.
//
// Needs quaternion.wgsl. Every contact is a PolyHit: normal from B (or the wall) to A, depth > 0, and one
// point, the depth-weighted mean of the manifold points (each halfway through the
// overlap), exactly as tumble-geom's PolyContact::point.
//
// The including module defines `fn shape_word(i: u32) -> vec4<f32>`: word i of
// the shape table. Indices are whole numbers stored as f32.
//
// f32 adaptations of the f64 tolerances: the near-tie margin between axes is
// 1e-6 of the sizes (tumble-geom: 1e-9), nearly parallel edges are skipped below
// sin θ = 1e-6 (tumble-geom: 1e-12); both only matter in a thin band where the two
// choices give nearly the same contact.

const POLY_BIG: f32 = 3.0e38;
const POLY_NONE: u32 = 0xffffffffu;
// Clipped polygon capacity: a face of at most 16 vertices clipped by a face of at most 16.
const POLY_MAX_POINTS: u32 = 32u;
const POLY_MAX_FACE: u32 = 16u;

struct PolyHit {
    hit: bool,
    // Unit, from B to A.
    normal: vec3<f32>,
    depth: f32,
    // Relative to B's centre for particle pairs, to the walls' origin for walls.
    point: vec3<f32>,
    // Depth-weighted mean distance of the manifold points from `point` (0 for one point):
    // the patch radius of twisting friction.
    spread: f32,
}

fn no_poly_hit() -> PolyHit {
    return PolyHit(false, vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0);
}

// ---- The shape table ----

struct ShapeHead {
    vs: u32,
    nv: u32,
    fs: u32,
    nf: u32,
    es: u32,
    ne: u32,
    radius: f32,
}

const SHAPE_HEADER_WORDS: u32 = 3u;

fn shape_head(s: u32) -> ShapeHead {
    let h0 = shape_word(SHAPE_HEADER_WORDS * s);
    let h1 = shape_word(SHAPE_HEADER_WORDS * s + 1u);
    return ShapeHead(u32(h0.x), u32(h0.y), u32(h0.z), u32(h0.w), u32(h1.x), u32(h1.y), h1.z);
}

// (volume / principal unit inertia: the inverse principal inertia per inverse mass; equivalent radius).
fn shape_inertia(s: u32) -> vec4<f32> {
    return shape_word(SHAPE_HEADER_WORDS * s + 2u);
}

fn shape_vertex(h: ShapeHead, i: u32) -> vec3<f32> {
    return shape_word(h.vs + i).xyz;
}

// (normal, offset): the face plane n · p = offset.
fn shape_face(h: ShapeHead, f: u32) -> vec4<f32> {
    return shape_word(h.fs + 2u * f);
}

// (loop start, loop length).
fn shape_face_loop(h: ShapeHead, f: u32) -> vec2<u32> {
    let w = shape_word(h.fs + 2u * f + 1u);
    return vec2<u32>(u32(w.x), u32(w.y));
}

fn shape_loop_vertex(start: u32, k: u32) -> u32 {
    let c = start + k;
    return u32(shape_word(c / 4u)[c % 4u]);
}

// (v0, v1, f0, f1).
fn shape_edge(h: ShapeHead, e: u32) -> vec4<u32> {
    return vec4<u32>(shape_word(h.es + e));
}

// The vertex farthest along `dir` (the first of equals).
fn shape_support(h: ShapeHead, dir: vec3<f32>) -> u32 {
    var best = 0u;
    var best_d = -POLY_BIG;
    for (var i = 0u; i < h.nv; i++) {
        let d = dot(shape_vertex(h, i), dir);
        if d > best_d {
            best_d = d;
            best = i;
        }
    }
    return best;
}

// ---- Manifolds ----

// The reference polygon, the polygon being clipped and its clipped copy; `poly_b`
// also holds the manifold points (xyz, depth) before the reduction to four.
var<private> poly_ref: array<vec3<f32>, 16>;
var<private> poly_a: array<vec4<f32>, 32>;
var<private> poly_b: array<vec4<f32>, 32>;
// The patch radius of the last manifold (manifold_point).
var<private> poly_spread: f32;

// Loads face f of shape h, mapped by p ↦ r p + t, into poly_ref (which = 0) or poly_a (which = 1).
fn load_face(h: ShapeHead, f: u32, r: mat3x3<f32>, t: vec3<f32>, which: u32) -> u32 {
    let lp = shape_face_loop(h, f);
    let n = min(lp.y, POLY_MAX_FACE);
    for (var k = 0u; k < n; k++) {
        let p = r * shape_vertex(h, shape_loop_vertex(lp.x, k)) + t;
        if which == 0u {
            poly_ref[k] = p;
        } else {
            poly_a[k] = vec4<f32>(p, 0.0);
        }
    }
    return n;
}

// Sutherland–Hodgman of poly_a (n points) against the half-space side · p ≤ off, back into poly_a.
fn clip_poly_a(n: u32, side: vec3<f32>, off: f32) -> u32 {
    var m = 0u;
    for (var k = 0u; k < n; k++) {
        let p = poly_a[k].xyz;
        let q = poly_a[(k + 1u) % n].xyz;
        let dp = dot(side, p) - off;
        let dq = dot(side, q) - off;
        if dp <= 0.0 && m < POLY_MAX_POINTS {
            poly_b[m] = vec4<f32>(p, 0.0);
            m++;
        }
        if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) && m < POLY_MAX_POINTS {
            poly_b[m] = vec4<f32>(p + (q - p) * (dp / (dp - dq)), 0.0);
            m++;
        }
    }
    for (var k = 0u; k < m; k++) {
        poly_a[k] = poly_b[k];
    }
    return m;
}

// The depth-weighted mean of at most four of the m manifold points in poly_b
// (xyz, depth): the deepest, the farthest from it, the one making the largest
// triangle with those, and the largest on the other side (tumble-geom's
// reduce_to_four, ties resolved the same way); n is the contact plane's normal.
// Sets poly_spread to the depth-weighted mean distance of those points from the
// mean (the patch radius of twisting friction; 0 for one point).
fn manifold_point(m: u32, n: vec3<f32>) -> vec3<f32> {
    var idx = array<u32, 4>(0u, 1u, 2u, 3u);
    var count = m;
    if m > 4u {
        var i0 = 0u;
        for (var k = 1u; k < m; k++) {
            if poly_b[k].w >= poly_b[i0].w {
                i0 = k;
            }
        }
        let p0 = poly_b[i0].xyz;
        var i1 = 0u;
        var far = dot(poly_b[0].xyz - p0, poly_b[0].xyz - p0);
        for (var k = 1u; k < m; k++) {
            let d2 = dot(poly_b[k].xyz - p0, poly_b[k].xyz - p0);
            if d2 >= far {
                far = d2;
                i1 = k;
            }
        }
        let e = poly_b[i1].xyz - p0;
        var i2 = 0u;
        var big = abs(dot(cross(e, poly_b[0].xyz - p0), n));
        for (var k = 1u; k < m; k++) {
            let a = abs(dot(cross(e, poly_b[k].xyz - p0), n));
            if a >= big {
                big = a;
                i2 = k;
            }
        }
        let sgn = select(-1.0, 1.0, dot(cross(e, poly_b[i2].xyz - p0), n) >= 0.0);
        var i3 = 0u;
        var low = sgn * dot(cross(e, poly_b[0].xyz - p0), n);
        for (var k = 1u; k < m; k++) {
            let a = sgn * dot(cross(e, poly_b[k].xyz - p0), n);
            if a < low {
                low = a;
                i3 = k;
            }
        }
        // The four in order, each once (by position).
        let chosen = array<u32, 4>(i0, i1, i2, i3);
        count = 0u;
        for (var j = 0u; j < 4u; j++) {
            var seen = false;
            for (var i = 0u; i < count; i++) {
                seen = seen || all(poly_b[idx[i]].xyz == poly_b[chosen[j]].xyz);
            }
            if !seen {
                idx[count] = chosen[j];
                count++;
            }
        }
    }
    var sum = vec3<f32>(0.0);
    var w = 0.0;
    for (var j = 0u; j < count; j++) {
        let pj = poly_b[idx[j]];
        sum += pj.xyz * pj.w;
        w += pj.w;
    }
    let mean = select(poly_b[idx[0]].xyz, sum / w, w > 0.0);
    var spread = 0.0;
    if count > 1u && w > 0.0 {
        for (var j = 0u; j < count; j++) {
            let pj = poly_b[idx[j]];
            spread += pj.w * length(pj.xyz - mean);
        }
        spread /= w;
    }
    poly_spread = spread;
    return mean;
}

// Face contact: the incident polygon (poly_a, n_inc points) clipped by the side
// planes of the reference polygon (poly_ref, n_ref points, counter-clockwise about
// ref_n, plane ref_n · p = ref_off); the points below the reference plane, each
// halfway through its overlap, reduced to four. `deepest` is used when rounding
// leaves nothing. Returns the manifold point (same frame as the polygons).
fn face_contact_point(n_ref: u32, ref_n: vec3<f32>, ref_off: f32, n_inc: u32, depth: f32, deepest: vec3<f32>) -> vec3<f32> {
    var n = n_inc;
    for (var k = 0u; k < n_ref; k++) {
        let r0 = poly_ref[k];
        let r1 = poly_ref[(k + 1u) % n_ref];
        let side = cross(r1 - r0, ref_n);
        n = clip_poly_a(n, side, dot(side, r0));
        if n == 0u {
            break;
        }
    }
    var m = 0u;
    for (var k = 0u; k < n; k++) {
        let p = poly_a[k].xyz;
        let d = ref_off - dot(ref_n, p);
        if d > 0.0 {
            poly_b[m] = vec4<f32>(p + ref_n * (0.5 * d), d);
            m++;
        }
    }
    if m == 0u {
        let d = max(ref_off - dot(ref_n, deepest), 0.0);
        poly_b[0] = vec4<f32>(deepest + ref_n * (0.5 * d), max(depth, d));
        m = 1u;
    }
    return manifold_point(m, ref_n);
}

// Closest points of segments p0 + s (p1 − p0) and q0 + t (q1 − q0), s, t ∈ [0, 1]; returns their midpoint.
fn segments_midpoint(p0: vec3<f32>, p1: vec3<f32>, q0: vec3<f32>, q1: vec3<f32>) -> vec3<f32> {
    let u = p1 - p0;
    let v = q1 - q0;
    let w = p0 - q0;
    let a = dot(u, u);
    let b = dot(u, v);
    let c = dot(v, v);
    let d = dot(u, w);
    let e = dot(v, w);
    let den = a * c - b * b;
    var s: f32;
    var t: f32;
    if den <= 1e-6 * a * c {
        // Parallel: the middle of the overlap of the projections.
        let t0 = clamp(-d / a, 0.0, 1.0);
        let t1 = clamp((b - d) / a, 0.0, 1.0);
        s = 0.5 * (t0 + t1);
        t = clamp((b * s + e) / c, 0.0, 1.0);
    } else {
        let s0 = clamp((b * e - c * d) / den, 0.0, 1.0);
        t = clamp((b * s0 + e) / c, 0.0, 1.0);
        s = clamp((b * t - d) / a, 0.0, 1.0);
    }
    return 0.5 * (p0 + u * s + q0 + v * t);
}

// ---- Polyhedron against polyhedron ----

// Polyhedron sa (orientation qa) against polyhedron sb (orientation qb), with
// d = x_a − x_b. The point is relative to x_b.
fn polyhedron_polyhedron(sa: u32, qa: vec4<f32>, sb: u32, qb: vec4<f32>, d: vec3<f32>) -> PolyHit {
    let ha = shape_head(sa);
    let hb = shape_head(sb);
    let reach = ha.radius + hb.radius;
    if dot(d, d) >= reach * reach {
        return no_poly_hit();
    }
    // Everything in B's body frame: A's points are r p + t.
    let qbi = quat_conj(qb);
    let t = quat_rotate(qbi, d);
    let r = quat_matrix(quat_mul(qbi, qa));
    let rt = transpose(r);

    // Faces of B: A's deepest vertex below each.
    var best_b = -POLY_BIG;
    var face_b = 0u;
    for (var f = 0u; f < hb.nf; f++) {
        let pl = shape_face(hb, f);
        let m = rt * pl.xyz;
        var low = POLY_BIG;
        for (var i = 0u; i < ha.nv; i++) {
            low = min(low, dot(shape_vertex(ha, i), m));
        }
        let s = low + dot(t, pl.xyz) - pl.w;
        if s >= 0.0 {
            return no_poly_hit();
        }
        if s > best_b {
            best_b = s;
            face_b = f;
        }
    }
    // Faces of A: B's deepest vertex below each.
    var best_a = -POLY_BIG;
    var face_a = 0u;
    for (var f = 0u; f < ha.nf; f++) {
        let pl = shape_face(ha, f);
        let n = r * pl.xyz;
        var low = POLY_BIG;
        for (var i = 0u; i < hb.nv; i++) {
            low = min(low, dot(shape_vertex(hb, i), n));
        }
        let s = low - (pl.w + dot(n, t));
        if s >= 0.0 {
            return no_poly_hit();
        }
        if s > best_a {
            best_a = s;
            face_a = f;
        }
    }
    // Edge pairs whose Gauss-map arcs cross (faces of the Minkowski difference),
    // only those shallower than the best face.
    var best_e = max(best_a, best_b);
    var edge_a = POLY_NONE;
    var edge_b = 0u;
    for (var ia = 0u; ia < ha.ne; ia++) {
        let ea = shape_edge(ha, ia);
        let an = r * shape_face(ha, ea.z).xyz;
        let bn = r * shape_face(ha, ea.w).xyz;
        let bxa = cross(bn, an);
        let p0 = r * shape_vertex(ha, ea.x) + t;
        let u = r * shape_vertex(ha, ea.y) + t - p0;
        for (var ib = 0u; ib < hb.ne; ib++) {
            let eb = shape_edge(hb, ib);
            let cn = shape_face(hb, eb.z).xyz;
            let dn = shape_face(hb, eb.w).xyz;
            let cba = -dot(cn, bxa);
            let dba = -dot(dn, bxa);
            if cba * dba >= 0.0 {
                continue;
            }
            let dxc = cross(dn, cn);
            let adc = dot(an, dxc);
            let bdc = dot(bn, dxc);
            if !(adc * bdc < 0.0 && cba * bdc > 0.0) {
                continue;
            }
            let q0 = shape_vertex(hb, eb.x);
            let v = shape_vertex(hb, eb.y) - q0;
            let n = cross(u, v);
            let len2 = dot(n, n);
            if len2 <= 1e-12 * dot(u, u) * dot(v, v) {
                continue; // parallel edges: a face axis covers them
            }
            var num = dot(n, p0 - q0);
            if dot(n, q0) < 0.0 {
                num = -num;
            }
            if num >= 0.0 {
                return no_poly_hit();
            }
            if num * num < best_e * best_e * len2 {
                best_e = num * inverseSqrt(len2);
                edge_a = ia;
                edge_b = ib;
            }
        }
    }

    // Minimum penetration; face contacts win near-ties.
    let tie = 2e-6 * reach;
    poly_spread = 0.0;
    var normal: vec3<f32>;
    var depth: f32;
    var point: vec3<f32>;
    if edge_a != POLY_NONE && best_e > max(best_a, best_b) + tie {
        let ea = shape_edge(ha, edge_a);
        let eb = shape_edge(hb, edge_b);
        let p0 = r * shape_vertex(ha, ea.x) + t;
        let p1 = r * shape_vertex(ha, ea.y) + t;
        let q0 = shape_vertex(hb, eb.x);
        let q1 = shape_vertex(hb, eb.y);
        normal = normalize(cross(p1 - p0, q1 - q0));
        if dot(normal, q0) < 0.0 {
            normal = -normal;
        }
        depth = -best_e;
        point = segments_midpoint(p0, p1, q0, q1);
    } else if best_b >= best_a - tie {
        // B's face is the reference, A's most anti-parallel face the incident one.
        let pl = shape_face(hb, face_b);
        let n_ref = load_face(hb, face_b, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(0.0), 0u);
        let m = rt * pl.xyz;
        var inc = 0u;
        var low = POLY_BIG;
        for (var f = 0u; f < ha.nf; f++) {
            let c = dot(shape_face(ha, f).xyz, m);
            if c < low {
                low = c;
                inc = f;
            }
        }
        let n_inc = load_face(ha, inc, r, t, 1u);
        let deepest = r * shape_vertex(ha, shape_support(ha, -m)) + t;
        normal = pl.xyz;
        depth = -best_b;
        point = face_contact_point(n_ref, pl.xyz, pl.w, n_inc, depth, deepest);
    } else {
        // A's face is the reference, B's most anti-parallel face the incident one.
        let pl = shape_face(ha, face_a);
        let n = r * pl.xyz;
        let n_ref = load_face(ha, face_a, r, t, 0u);
        var inc = 0u;
        var low = POLY_BIG;
        for (var f = 0u; f < hb.nf; f++) {
            let c = dot(shape_face(hb, f).xyz, n);
            if c < low {
                low = c;
                inc = f;
            }
        }
        let n_inc = load_face(hb, inc, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(0.0), 1u);
        let deepest = shape_vertex(hb, shape_support(hb, -n));
        normal = -n;
        depth = -best_a;
        point = face_contact_point(n_ref, n, pl.w + dot(n, t), n_inc, depth, deepest);
    }
    return PolyHit(true, quat_rotate(qb, normal), depth, quat_rotate(qb, point), poly_spread);
}

// ---- Sphere against polyhedron ----

// A sphere (radius) at x_a against polyhedron sb (orientation qb), d = x_a − x_b.
// Normal from the polyhedron to the sphere; the point is relative to x_b.
fn sphere_polyhedron(radius: f32, sb: u32, qb: vec4<f32>, d: vec3<f32>) -> PolyHit {
    let h = shape_head(sb);
    let c = quat_rotate(quat_conj(qb), d);
    let reach = h.radius + radius;
    if dot(c, c) >= reach * reach {
        return no_poly_hit();
    }
    var best = -POLY_BIG;
    var best_f = 0u;
    for (var f = 0u; f < h.nf; f++) {
        let pl = shape_face(h, f);
        let s = dot(pl.xyz, c) - pl.w;
        if s > best {
            best = s;
            best_f = f;
        }
    }
    var normal: vec3<f32>;
    var depth: f32;
    var q: vec3<f32>;
    var found = false;
    if best <= 0.0 {
        // Inside: leave through the nearest face.
        let n = shape_face(h, best_f).xyz;
        q = c - n * best;
        normal = n;
        depth = radius - best;
        found = true;
    }
    // Outside: a face whose plane the centre is in front of and whose foot lies inside the face.
    for (var f = 0u; f < h.nf && !found; f++) {
        let pl = shape_face(h, f);
        let s = dot(pl.xyz, c) - pl.w;
        if s <= 0.0 {
            continue;
        }
        let foot = c - pl.xyz * s;
        let lp = shape_face_loop(h, f);
        var inside = true;
        for (var k = 0u; k < lp.y; k++) {
            let a = shape_vertex(h, shape_loop_vertex(lp.x, k));
            let b = shape_vertex(h, shape_loop_vertex(lp.x, (k + 1u) % lp.y));
            inside = inside && dot(cross(b - a, foot - a), pl.xyz) >= 0.0;
        }
        if inside {
            q = foot;
            normal = pl.xyz;
            depth = radius - length(c - foot);
            found = true;
        }
    }
    if !found {
        // Edge or vertex region: the closest point over the edges of faces the centre is in front of.
        var closest = POLY_BIG;
        for (var e = 0u; e < h.ne; e++) {
            let ed = shape_edge(h, e);
            let f0 = shape_face(h, ed.z);
            let f1 = shape_face(h, ed.w);
            if !(dot(f0.xyz, c) > f0.w || dot(f1.xyz, c) > f1.w) {
                continue;
            }
            let a = shape_vertex(h, ed.x);
            let ab = shape_vertex(h, ed.y) - a;
            let s = clamp(dot(c - a, ab) / dot(ab, ab), 0.0, 1.0);
            let p = a + ab * s;
            let d2 = dot(c - p, c - p);
            if d2 < closest {
                closest = d2;
                q = p;
            }
        }
        let dist = sqrt(closest);
        normal = (c - q) / dist;
        depth = radius - dist;
    }
    if !(depth > 0.0) {
        return no_poly_hit();
    }
    return PolyHit(true, quat_rotate(qb, normal), depth, quat_rotate(qb, q - normal * (0.5 * depth)), 0.0);
}

// ---- Polyhedron against walls (coordinates relative to one origin) ----

// Polyhedron s at x (orientation q) against the plane through `point` with unit `normal`.
fn polyhedron_plane(s: u32, q: vec4<f32>, x: vec3<f32>, point: vec3<f32>, normal: vec3<f32>) -> PolyHit {
    let h = shape_head(s);
    let height = dot(normal, x - point);
    if height >= h.radius {
        return no_poly_hit();
    }
    let n = quat_rotate(quat_conj(q), normal);
    var m = 0u;
    var depth = 0.0;
    for (var i = 0u; i < h.nv; i++) {
        let v = shape_vertex(h, i);
        let d = -(height + dot(n, v));
        if d > 0.0 && m < POLY_MAX_POINTS {
            depth = max(depth, d);
            poly_b[m] = vec4<f32>(x + quat_rotate(q, v) + normal * (0.5 * d), d);
            m++;
        }
    }
    if m == 0u {
        return no_poly_hit();
    }
    let mean = manifold_point(m, normal);
    return PolyHit(true, normal, depth, mean, poly_spread);
}

// Polyhedron s at x (orientation q) against a quad (corners counter-clockwise
// about `normal`), one- or two-sided: separating axes over the quad's normal, the
// polyhedron's faces and the cross products of its edges with the quad's edges.
fn polyhedron_quad(s: u32, q: vec4<f32>, x: vec3<f32>, corners_in: array<vec3<f32>, 4>, normal: vec3<f32>, two_sided: bool) -> PolyHit {
    var corners = corners_in;
    let h = shape_head(s);
    let height = dot(normal, x - corners[0]);
    if abs(height) >= h.radius || (!two_sided && height <= 0.0) {
        return no_poly_hit();
    }
    // The polyhedron's body frame.
    let qi = quat_conj(q);
    var qc: array<vec3<f32>, 4>;
    for (var k = 0u; k < 4u; k++) {
        qc[k] = quat_rotate(qi, corners[k] - x);
    }
    let qn = quat_rotate(qi, normal);
    let tie = 2e-6 * h.radius;
    // Axis kinds: 0 quad face (its side in `face_sign`), 1 polyhedron face, 2 edge pair.
    var best_depth = POLY_BIG;
    var best_m = vec3<f32>(0.0);
    var best_kind = POLY_NONE;
    var best_i = 0u;
    var best_k = 0u;
    var face_sign = 1.0;

    // Quad normal, both sides.
    let h0 = dot(qn, qc[0]);
    var low = POLY_BIG;
    var high = -POLY_BIG;
    for (var i = 0u; i < h.nv; i++) {
        let dv = dot(shape_vertex(h, i), qn);
        low = min(low, dv);
        high = max(high, dv);
    }
    let front = h0 - low;
    let back = high - h0;
    if front <= 0.0 || back <= 0.0 {
        return no_poly_hit();
    }
    best_depth = front;
    best_m = qn;
    best_kind = 0u;
    if two_sided && back < best_depth - tie {
        best_depth = back;
        best_m = -qn;
        face_sign = -1.0;
    }
    // Polyhedron faces: m = −n_f.
    for (var f = 0u; f < h.nf; f++) {
        let pl = shape_face(h, f);
        var lo = POLY_BIG;
        for (var k = 0u; k < 4u; k++) {
            lo = min(lo, dot(qc[k], pl.xyz));
        }
        let depth = pl.w - lo;
        if depth <= 0.0 {
            return no_poly_hit();
        }
        let m = -pl.xyz;
        if (two_sided || dot(m, qn) >= -1e-6) && depth < best_depth - tie {
            best_depth = depth;
            best_m = m;
            best_kind = 1u;
            best_i = f;
        }
    }
    // Edge pairs, both orientations.
    for (var e = 0u; e < h.ne; e++) {
        let ed = shape_edge(h, e);
        let u = shape_vertex(h, ed.y) - shape_vertex(h, ed.x);
        for (var k = 0u; k < 4u; k++) {
            let v = qc[(k + 1u) % 4u] - qc[k];
            let mm = cross(u, v);
            if dot(mm, mm) <= 1e-12 * dot(u, u) * dot(v, v) {
                continue;
            }
            let m0 = normalize(mm);
            for (var side = 0u; side < 2u; side++) {
                let m = select(-m0, m0, side == 0u);
                var qmax = -POLY_BIG;
                for (var j = 0u; j < 4u; j++) {
                    qmax = max(qmax, dot(qc[j], m));
                }
                var pmin = POLY_BIG;
                for (var i = 0u; i < h.nv; i++) {
                    pmin = min(pmin, dot(shape_vertex(h, i), m));
                }
                let depth = qmax - pmin;
                if depth <= 0.0 {
                    return no_poly_hit();
                }
                if (two_sided || dot(m, qn) >= -1e-6) && depth < best_depth - tie {
                    best_depth = depth;
                    best_m = m;
                    best_kind = 2u;
                    best_i = e;
                    best_k = k;
                }
            }
        }
    }
    poly_spread = 0.0;
    var point: vec3<f32>;
    if best_kind == 0u {
        let n = qn * face_sign;
        for (var k = 0u; k < 4u; k++) {
            poly_ref[k] = select(qc[3u - k], qc[k], face_sign > 0.0);
        }
        var inc = 0u;
        var lo = POLY_BIG;
        for (var f = 0u; f < h.nf; f++) {
            let c = dot(shape_face(h, f).xyz, n);
            if c < lo {
                lo = c;
                inc = f;
            }
        }
        let n_inc = load_face(h, inc, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(0.0), 1u);
        point = face_contact_point(4u, n, dot(n, qc[0]), n_inc, best_depth, shape_vertex(h, shape_support(h, -n)));
    } else if best_kind == 1u {
        let pl = shape_face(h, best_i);
        let n_ref = load_face(h, best_i, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(0.0), 0u);
        var deepest = qc[0];
        for (var k = 0u; k < 4u; k++) {
            poly_a[k] = vec4<f32>(qc[k], 0.0);
            if dot(qc[k], pl.xyz) < dot(deepest, pl.xyz) {
                deepest = qc[k];
            }
        }
        point = face_contact_point(n_ref, pl.xyz, pl.w, 4u, best_depth, deepest);
    } else {
        let ed = shape_edge(h, best_i);
        point = segments_midpoint(shape_vertex(h, ed.x), shape_vertex(h, ed.y), qc[best_k], qc[(best_k + 1u) % 4u]);
    }
    return PolyHit(true, quat_rotate(q, best_m), best_depth, x + quat_rotate(q, point), poly_spread);
}

// Polyhedron s at x (orientation q) against a cylinder (axis from `point` along the
// unit `axis`, `length` long, `radius`): inside, the drum shell; outside, a pipe.
// The contact counts while the centre projects onto the axis within the length.
fn polyhedron_cylinder(s: u32, q: vec4<f32>, x: vec3<f32>, point: vec3<f32>, axis: vec3<f32>, radius: f32, len: f32, inside: bool) -> PolyHit {
    let h = shape_head(s);
    let rel = x - point;
    let along = dot(rel, axis);
    if along < 0.0 || along > len {
        return no_poly_hit();
    }
    let rho = length(rel - axis * along);
    if (inside && rho + h.radius <= radius) || (!inside && rho - h.radius >= radius) {
        return no_poly_hit();
    }
    if inside {
        // Vertices beyond the shell, each pushed towards the axis.
        var m = 0u;
        var depth = 0.0;
        var sum = vec3<f32>(0.0);
        for (var i = 0u; i < h.nv; i++) {
            let w = x + quat_rotate(q, shape_vertex(h, i));
            let rv = (w - point) - axis * dot(w - point, axis);
            let l = length(rv);
            let d = l - radius;
            if d > 0.0 && m < POLY_MAX_POINTS {
                let inward = -rv / l;
                poly_b[m] = vec4<f32>(w + inward * (0.5 * d), d);
                m++;
                depth = max(depth, d);
                sum += inward * d;
            }
        }
        if m == 0u {
            return no_poly_hit();
        }
        let normal = normalize(sum);
        let mean = manifold_point(m, normal);
    return PolyHit(true, normal, depth, mean, poly_spread);
    }
    // Pipe: the polyhedron's shadow across the axis (gift-wrapped, counter-clockwise
    // about the axis) against the circle.
    var t1 = cross(axis, vec3<f32>(1.0, 0.0, 0.0));
    if dot(t1, t1) < 0.1 {
        t1 = cross(axis, vec3<f32>(0.0, 1.0, 0.0));
    }
    t1 = normalize(t1);
    let t2 = cross(axis, t1);
    let eps = 1e-6 * h.radius;
    var start = 0u;
    var start_2d = vec2<f32>(POLY_BIG);
    for (var i = 0u; i < h.nv; i++) {
        let rv = rel + quat_rotate(q, shape_vertex(h, i));
        let p = vec2<f32>(dot(rv, t1), dot(rv, t2));
        if p.x < start_2d.x || (p.x == start_2d.x && p.y < start_2d.y) {
            start_2d = p;
            start = i;
        }
    }
    var nearest_d = -POLY_BIG;
    var nearest_out = vec3<f32>(0.0);
    var nearest_a = 0u;
    var nearest_b = 0u;
    var closest = POLY_BIG;
    var closest_a = 0u;
    var closest_b = 0u;
    var closest_t = 0.0;
    var cur = start;
    for (var iter = 0u; iter <= h.nv; iter++) {
        let rc = rel + quat_rotate(q, shape_vertex(h, cur));
        let pc = vec2<f32>(dot(rc, t1), dot(rc, t2));
        var nxt = POLY_NONE;
        var pn = pc;
        for (var i = 0u; i < h.nv; i++) {
            let ri = rel + quat_rotate(q, shape_vertex(h, i));
            let pi = vec2<f32>(dot(ri, t1), dot(ri, t2));
            let di = pi - pc;
            if dot(di, di) <= eps * eps {
                continue;
            }
            if nxt == POLY_NONE {
                nxt = i;
                pn = pi;
                continue;
            }
            let dn = pn - pc;
            let c = dn.x * di.y - dn.y * di.x;
            let scale = eps * sqrt(dot(dn, dn));
            if c < -scale || (abs(c) <= scale && dot(di, di) > dot(dn, dn)) {
                nxt = i;
                pn = pi;
            }
        }
        if nxt == POLY_NONE {
            break;
        }
        // The shadow's edge cur → nxt, in 3D (radial parts).
        let a3 = rel + quat_rotate(q, shape_vertex(h, cur));
        let b3 = rel + quat_rotate(q, shape_vertex(h, nxt));
        let a = a3 - axis * dot(a3, axis);
        let e = (b3 - axis * dot(b3, axis)) - a;
        let out = normalize(cross(e, axis));
        let dl = -dot(out, a);
        if dl > nearest_d {
            nearest_d = dl;
            nearest_out = out;
            nearest_a = cur;
            nearest_b = nxt;
        }
        let tt = clamp(-dot(a, e) / dot(e, e), 0.0, 1.0);
        let f = a + e * tt;
        if dot(f, f) < closest {
            closest = dot(f, f);
            closest_a = cur;
            closest_b = nxt;
            closest_t = tt;
        }
        cur = nxt;
        if dot(pn - start_2d, pn - start_2d) <= eps * eps {
            break;
        }
    }
    var normal: vec3<f32>;
    var depth: f32;
    var ia = closest_a;
    var ib = closest_b;
    var tt = closest_t;
    if nearest_d <= 0.0 {
        // The axis pierces the shadow: the nearest edge has to clear the circle.
        ia = nearest_a;
        ib = nearest_b;
        let a3 = rel + quat_rotate(q, shape_vertex(h, ia));
        let b3 = rel + quat_rotate(q, shape_vertex(h, ib));
        let a = a3 - axis * dot(a3, axis);
        let e = (b3 - axis * dot(b3, axis)) - a;
        tt = clamp(-dot(a, e) / dot(e, e), 0.0, 1.0);
        normal = -nearest_out;
        depth = radius - nearest_d;
    } else {
        let a3 = rel + quat_rotate(q, shape_vertex(h, ia));
        let b3 = rel + quat_rotate(q, shape_vertex(h, ib));
        let a = a3 - axis * dot(a3, axis);
        let rr = a + ((b3 - axis * dot(b3, axis)) - a) * tt;
        let dist = sqrt(closest);
        normal = rr / dist;
        depth = radius - dist;
    }
    if !(depth > 0.0) {
        return no_poly_hit();
    }
    let wa = x + quat_rotate(q, shape_vertex(h, ia));
    let wb = x + quat_rotate(q, shape_vertex(h, ib));
    let surface = wa + (wb - wa) * tt;
    return PolyHit(true, normal, depth, surface + normal * (0.5 * depth), 0.0);
}

// A wall table entry (geometry.wgsl layout: w0 = (kind, material, flag, _), then points and directions).
fn polyhedron_wall(s: u32, q: vec4<f32>, x: vec3<f32>, w: array<vec4<f32>, 6>) -> PolyHit {
    let kind = w[0].x;
    if kind == 0.0 {
        return polyhedron_plane(s, q, x, w[1].xyz, w[5].xyz);
    }
    if kind == 1.0 {
        let corners = array<vec3<f32>, 4>(w[1].xyz, w[2].xyz, w[3].xyz, w[4].xyz);
        return polyhedron_quad(s, q, x, corners, w[5].xyz, w[0].z != 0.0);
    }
    return polyhedron_cylinder(s, q, x, w[1].xyz, w[2].xyz, w[3].x, w[3].y, w[0].z != 0.0);
}
