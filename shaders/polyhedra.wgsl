// Convex polyhedra in f32: quaternion helpers, the shape table (shapes.rs) and
// the narrow phase of tumble-geom ported to WGSL: polyhedron–polyhedron
// (separating axes: face normals both ways and the edge pairs that form faces of
// the Minkowski difference, minimum penetration, the incident face clipped by the
// reference face, at most four points), sphere–polyhedron, and a polyhedron
// against a plane, a quad and a cylinder (drum shell inside, pipe outside).
// Lifters (prisms) go through polyhedron–polyhedron as table shapes.
//
// This file holds what the pairs share: PolyHit, the shape table and the manifolds;
// polyhedron_polyhedron.wgsl, sphere_polyhedron.wgsl and polyhedron_walls.wgsl hold the pairs.
// Needs quaternion.wgsl. Every contact is a PolyHit: normal from B (or the wall) to A, depth > 0, and one
// point, the depth-weighted mean of the manifold points (each halfway through the
// overlap), exactly as tumble-geom's PolyContact::point.
//
// The including module defines `fn shape_word(i: u32) -> vec4<f32>`: word i of
// the shape table. Indices are whole numbers stored as f32. Capacities (MAX_FACE_VERTICES,
// MANIFOLD_POINTS) and the header size (SHAPE_HEADER_WORDS) are prelude constants.
//
// f32 adaptations of the f64 tolerances: the near-tie margin between axes is
// 1e-6 of the sizes (tumble-geom: 1e-9), nearly parallel edges are skipped below
// sin θ = 1e-6 (tumble-geom: 1e-12); both only matter in a thin band where the two
// choices give nearly the same contact.

const POLY_BIG: f32 = 3.0e38;
const POLY_NONE: u32 = 0xffffffffu;

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
    return u32(shape_word(c / LOOP_INDICES_PER_WORD)[c % LOOP_INDICES_PER_WORD]);
}

// (v0, v1, f0, f1).
fn shape_edge(h: ShapeHead, e: u32) -> vec4<u32> {
    return vec4<u32>(shape_word(h.es + e));
}

// The vertex farthest along `dir` (the first of equals).
// Least v·m over the vertices v of h (body frame).
fn shape_min_dot(h: ShapeHead, m: vec3<f32>) -> f32 {
    var low = POLY_BIG;
    for (var i = 0u; i < h.nv; i++) {
        low = min(low, dot(shape_vertex(h, i), m));
    }
    return low;
}

// The face of h most anti-parallel to n: the incident face against a reference face of normal n.
fn incident_face(h: ShapeHead, n: vec3<f32>) -> u32 {
    var inc = 0u;
    var low = POLY_BIG;
    for (var f = 0u; f < h.nf; f++) {
        let c = dot(shape_face(h, f).xyz, n);
        if c < low {
            low = c;
            inc = f;
        }
    }
    return inc;
}

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
var<private> poly_ref: array<vec3<f32>, MAX_FACE_VERTICES>;
var<private> poly_a: array<vec4<f32>, MANIFOLD_POINTS>;
var<private> poly_b: array<vec4<f32>, MANIFOLD_POINTS>;
// The patch radius of the last manifold (manifold_point).
var<private> poly_spread: f32;

// Loads face f of shape h, mapped by p ↦ r p + t, into poly_ref (which = 0) or poly_a (which = 1).
fn load_face(h: ShapeHead, f: u32, r: mat3x3<f32>, t: vec3<f32>, which: u32) -> u32 {
    let lp = shape_face_loop(h, f);
    let n = min(lp.y, MAX_FACE_VERTICES);
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
        if dp <= 0.0 && m < MANIFOLD_POINTS {
            poly_b[m] = vec4<f32>(p, 0.0);
            m++;
        }
        if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) && m < MANIFOLD_POINTS {
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
