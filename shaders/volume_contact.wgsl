// Overlap-volume contacts in f32 (tumble-geom's overlap_volume.rs and volume_contact.rs): the
// overlap of polyhedron A with polyhedron B or a wall's solid, its volume V, the area vector S
// and moment M of B's faces inside A (V's derivatives: the force on A per unit w'(V) is S, the
// torque about x_A is M − x_A × S), then the corners of each body inside the other (smoothed
// depths) and the parts of their edges inside the other (three Gauss points per piece on which
// one face is the nearest). Needs polyhedra.wgsl (the shape table, poly_a and poly_b).
//
// The boundary of A ∩ B is A's faces clipped by B's planes and B's faces clipped by A's planes;
// both are accumulated in a frame whose origin lies near the overlap (the separating-axis contact
// point for pairs, in B's body frame; the foot of A's centre on the surface for walls, in the
// world frame), so the sums stay of the size of V. A face lying in a plane of the other body with
// the same outward normal counts half. A wall's solid: a plane's half-space (its face a square of
// half-size 2 R_A), a quad's semi-infinite prism (the quad and four side rectangles 2 R_A deep;
// its corners and rim are the solid's), a cylinder's half-space behind its tangent plane at the
// azimuth of A's centre, with the azimuth term in the push (corners and edges meet the true
// cylinder, edges as material points).
//
// volume_pair / volume_wall return the moments and leave the frame in private variables;
// volume_points then calls `point_load(point, depth, gradient, weight)` for every corner and
// edge point, which the including module defines (the contact pass applies the normal law there,
// the test harness sums them). Points and vectors given to point_load are in the world
// orientation relative to the caller's origin (x_B for pairs, the walls' origin for walls).

struct VolumeHit {
    hit: bool,
    volume: f32,
    // −∂V/∂x_A, −∂V/∂θ_A about x_A, −∂V/∂θ_B about x_B (zero for walls).
    push: vec3<f32>,
    turn_a: vec3<f32>,
    turn_b: vec3<f32>,
    // Unit push (B to A), the point where the tangential force acts, |S| and the penetration depth.
    normal: vec3<f32>,
    point: vec3<f32>,
    area: f32,
    depth: f32,
}

fn no_volume_hit() -> VolumeHit {
    return VolumeHit(false, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0);
}

// (largest face area, its corners, its perimeter) of shape s.
fn shape_contact(s: u32) -> vec3<f32> {
    return shape_word(SHAPE_HEADER_WORDS * s + 3u).xyz;
}

// The law's multiple per unit length of an edge of shape s (corners / perimeter of its largest face).
fn shape_edge_density(s: u32) -> f32 {
    let c = shape_contact(s);
    return c.y / c.z;
}

// How many times a face of shape s lying on a larger face meets the law: 1 + 2 × its corners.
fn shape_face_on_weight(s: u32) -> f32 {
    return 1.0 + 2.0 * shape_contact(s).y;
}

// The running sums: volume, ∫x dV, S, M (relative to the origin), deepest point below B's plane 0.
var<private> vol_volume: f32;
var<private> vol_first: vec3<f32>;
var<private> vol_area: vec3<f32>;
var<private> vol_moment: vec3<f32>;
var<private> vol_depth: f32;
// The frame: both bodies' planes (m, offset) relative to the origin.
var<private> vc_planes_a: array<vec4<f32>, MANIFOLD_POINTS>;
var<private> vc_planes_b: array<vec4<f32>, MANIFOLD_POINTS>;
var<private> vc_count_a: u32;
var<private> vc_count_b: u32;
// A's map into the frame (p ↦ vc_r p + vc_t), B's (pairs: p ↦ p + vc_tb), the rotation and shift
// from the frame to the caller's (world orientation, relative to x_B or the walls' origin).
var<private> vc_sa: u32;
var<private> vc_sb: u32;
var<private> vc_r: mat3x3<f32>;
var<private> vc_t: vec3<f32>;
var<private> vc_tb: vec3<f32>;
var<private> vc_out_q: vec4<f32>;
var<private> vc_out_shift: vec3<f32>;
var<private> vc_tau: f32;
var<private> vc_density_a: f32;
var<private> vc_density_b: f32;
// What B is: VC_SHAPE, VC_PLANES (plane or quad; wall_quad holds the quad's corners when
// vc_quad) or VC_CYLINDER (point, axis, radius, inside).
var<private> vc_kind: u32;
var<private> vc_quad: bool;
var<private> wall_quad: array<vec3<f32>, 4>;
var<private> vc_cyl_point: vec3<f32>;
var<private> vc_cyl_axis: vec3<f32>;
var<private> vc_cyl_radius: f32;
var<private> vc_cyl_inside: bool;

const VC_SHAPE: u32 = 0u;
const VC_PLANES: u32 = 1u;
const VC_CYLINDER: u32 = 2u;

fn volume_reset() {
    vol_volume = 0.0;
    vol_first = vec3<f32>(0.0);
    vol_area = vec3<f32>(0.0);
    vol_moment = vec3<f32>(0.0);
    vol_depth = 0.0;
}

// Adds the polygon poly_a[0..n]: its share of the volume (fan tetrahedra from the origin) with
// weight wv, of S and M with weight wa.
fn volume_add(n: u32, wv: f32, wa: f32) {
    let p0 = poly_a[0].xyz;
    for (var k = 1u; k + 1u < n; k++) {
        let p1 = poly_a[k].xyz;
        let p2 = poly_a[k + 1u].xyz;
        let six_v = dot(p0, cross(p1, p2));
        vol_volume += wv * six_v / 6.0;
        vol_first += (wv * six_v / 24.0) * (p0 + p1 + p2);
        if wa != 0.0 {
            let tri = 0.5 * cross(p1 - p0, p2 - p0);
            vol_area += wa * tri;
            vol_moment += wa * cross((p0 + p1 + p2) / 3.0, tri);
        }
    }
}

// poly_a[0..n] (outward normal fn_) clipped to m · p ≤ off: (new count, 1 when it lies in the
// plane facing the same way); count 0 when nothing of positive area is left.
fn volume_clip(n: u32, fn_: vec3<f32>, m: vec3<f32>, off: f32, eps: f32) -> vec2<u32> {
    var inside = true;
    var outside = true;
    var flat = true;
    for (var k = 0u; k < n; k++) {
        let h = dot(m, poly_a[k].xyz) - off;
        inside = inside && h <= eps;
        outside = outside && h >= -eps;
        flat = flat && abs(h) <= eps;
    }
    if flat {
        return select(vec2<u32>(0u, 0u), vec2<u32>(n, 1u), dot(fn_, m) > 0.0);
    }
    if inside {
        return vec2<u32>(n, 0u);
    }
    if outside {
        return vec2<u32>(0u, 0u);
    }
    var c = 0u;
    for (var k = 0u; k < n; k++) {
        let p = poly_a[k].xyz;
        let q = poly_a[(k + 1u) % n].xyz;
        let hp = dot(m, p) - off;
        let hq = dot(m, q) - off;
        if hp <= eps && c < MANIFOLD_POINTS {
            poly_b[c] = vec4<f32>(p, 0.0);
            c++;
        }
        if ((hp < -eps && hq > eps) || (hp > eps && hq < -eps)) && c < MANIFOLD_POINTS {
            poly_b[c] = vec4<f32>(p + (q - p) * (hp / (hp - hq)), 0.0);
            c++;
        }
    }
    for (var k = 0u; k < c; k++) {
        poly_a[k] = poly_b[k];
    }
    return vec2<u32>(select(0u, c, c >= 3u), 0u);
}

// Clips poly_a[0..n] (outward normal fn_) by the planes of A (other_is_a) or of B: the count left
// and whether it was shared with one of them.
fn volume_clip_all(n_in: u32, fn_: vec3<f32>, other_is_a: bool, eps: f32) -> vec2<u32> {
    var n = n_in;
    var shared_ = 0u;
    let count = select(vc_count_b, vc_count_a, other_is_a);
    for (var g = 0u; g < count && n > 0u; g++) {
        let pl = select(vc_planes_b[g], vc_planes_a[g], other_is_a);
        let c = volume_clip(n, fn_, pl.xyz, pl.w, eps);
        n = c.x;
        shared_ = max(shared_, c.y);
    }
    return vec2<u32>(n, shared_);
}

// Loads face f of shape h, mapped by p ↦ r p + t, into poly_a; returns its outward normal
// (r n_f) and vertex count in w.
fn volume_load_face(h: ShapeHead, f: u32, r: mat3x3<f32>, t: vec3<f32>) -> vec4<f32> {
    let lp = shape_face_loop(h, f);
    let n = min(lp.y, MAX_FACE_VERTICES);
    for (var k = 0u; k < n; k++) {
        poly_a[k] = vec4<f32>(r * shape_vertex(h, shape_loop_vertex(lp.x, k)) + t, 0.0);
    }
    return vec4<f32>(r * shape_face(h, f).xyz, f32(n));
}

// Loads the planes of shape h mapped by (r, t) into vc_planes_a (which_a) or vc_planes_b.
fn volume_load_planes(h: ShapeHead, r: mat3x3<f32>, t: vec3<f32>, which_a: bool) {
    let n = min(h.nf, MANIFOLD_POINTS);
    for (var f = 0u; f < n; f++) {
        let pl = shape_face(h, f);
        let m = r * pl.xyz;
        let plane = vec4<f32>(m, pl.w + dot(m, t));
        if which_a {
            vc_planes_a[f] = plane;
        } else {
            vc_planes_b[f] = plane;
        }
    }
    if which_a {
        vc_count_a = n;
    } else {
        vc_count_b = n;
    }
}

// Clips A's faces by B's planes (volume only, tracking the depth below B's plane 0) and then
// calls the including code for B's faces.
fn volume_clip_a(eps: f32) {
    let ha = shape_head(vc_sa);
    for (var f = 0u; f < ha.nf; f++) {
        let face = volume_load_face(ha, f, vc_r, vc_t);
        let c = volume_clip_all(u32(face.w), face.xyz, false, eps);
        if c.x > 0u {
            for (var k = 0u; k < c.x; k++) {
                vol_depth = max(vol_depth, vc_planes_b[0].w - dot(vc_planes_b[0].xyz, poly_a[k].xyz));
            }
            volume_add(c.x, select(1.0, 0.5, c.y != 0u), 0.0);
        }
    }
}

// Adds B's clipped face (poly_a[0..n], outward normal fn_) to the sums.
fn volume_clip_b_face(n: u32, fn_: vec3<f32>, eps: f32) {
    let c = volume_clip_all(n, fn_, true, eps);
    if c.x > 0u {
        let w = select(1.0, 0.5, c.y != 0u);
        volume_add(c.x, w, w);
    }
}

// The hit from the sums: push (S plus any azimuth term), turns about the centres xa, xb (relative
// to the origin), the action point; all still in the frame.
fn volume_finish(push: vec3<f32>, xa: vec3<f32>, xb: vec3<f32>, depth: f32) -> VolumeHit {
    var hit = no_volume_hit();
    let area = length(vol_area);
    if !(vol_volume > 0.0) || area <= 0.0 || dot(push, push) <= 0.0 {
        return hit;
    }
    hit.hit = true;
    hit.volume = vol_volume;
    hit.push = push;
    hit.turn_a = vol_moment - cross(xa, vol_area);
    hit.turn_b = -(vol_moment - cross(xb, vol_area));
    hit.normal = normalize(push);
    let centroid = vol_first / vol_volume;
    hit.point = centroid + cross(vol_area, vol_moment - cross(centroid, vol_area)) / dot(vol_area, vol_area);
    hit.area = area;
    hit.depth = depth;
    return hit;
}

// The hit in the caller's frame (world orientation, relative to x_B or the walls' origin).
fn volume_out(hit_in: VolumeHit) -> VolumeHit {
    var hit = hit_in;
    hit.push = quat_rotate(vc_out_q, hit.push);
    hit.turn_a = quat_rotate(vc_out_q, hit.turn_a);
    hit.turn_b = quat_rotate(vc_out_q, hit.turn_b);
    hit.normal = quat_rotate(vc_out_q, hit.normal);
    hit.point = quat_rotate(vc_out_q, hit.point) + vc_out_shift;
    return hit;
}

// Polyhedron sa (orientation qa) against polyhedron sb (qb), d = x_a − x_b; results relative to
// x_b in the world orientation. B's edges carry `b_density` per unit length.
fn volume_pair(sa: u32, qa: vec4<f32>, sb: u32, qb: vec4<f32>, d: vec3<f32>, b_density: f32) -> VolumeHit {
    let gate = polyhedron_polyhedron(sa, qa, sb, qb, d);
    if !gate.hit {
        return no_volume_hit();
    }
    let ha = shape_head(sa);
    let hb = shape_head(sb);
    // B's body frame, origin at the gate's contact point: A's points are r p + t, B's p − o.
    let qbi = quat_conj(qb);
    let o = quat_rotate(qbi, gate.point);
    vc_kind = VC_SHAPE;
    vc_sa = sa;
    vc_sb = sb;
    vc_r = quat_matrix(quat_mul(qbi, qa));
    vc_t = quat_rotate(qbi, d) - o;
    vc_tb = -o;
    vc_out_q = qb;
    vc_out_shift = quat_rotate(qb, o);
    vc_tau = CORNER_SMOOTHING * min(ha.radius, hb.radius);
    vc_density_a = shape_edge_density(sa);
    vc_density_b = b_density;
    let eye = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    volume_load_planes(ha, vc_r, vc_t, true);
    volume_load_planes(hb, eye, vc_tb, false);
    let eps = 1e-6 * max(ha.radius, hb.radius);
    volume_reset();
    volume_clip_a(eps);
    for (var g = 0u; g < hb.nf; g++) {
        let face = volume_load_face(hb, g, eye, vc_tb);
        volume_clip_b_face(u32(face.w), face.xyz, eps);
    }
    return volume_out(volume_finish(vol_area, vc_t, vc_tb, gate.depth));
}

// Face g of a plane or quad wall's solid into poly_a, counter-clockwise about its outward normal
// (returned): face 0 the quad (wall_quad), faces 1–4 its sides, `depth` deep behind it.
fn wall_load_face(g: u32, depth: f32) -> vec3<f32> {
    let m = vc_planes_b[g].xyz;
    var p: array<vec3<f32>, 4>;
    if g == 0u {
        p = wall_quad;
    } else {
        let a = wall_quad[g - 1u];
        let b = wall_quad[g % 4u];
        let back = vc_planes_b[0].xyz * depth;
        p = array<vec3<f32>, 4>(a, b, b - back, a - back);
    }
    let flip = dot(cross(p[1] - p[0], p[2] - p[0]), m) < 0.0;
    for (var k = 0u; k < 4u; k++) {
        poly_a[k] = vec4<f32>(select(p[k], p[3u - k], flip), 0.0);
    }
    return m;
}

// A square of half-size `half` about the origin in the plane through it with normal m, as wall_quad.
fn wall_square(m: vec3<f32>, half: f32) {
    var u = cross(m, vec3<f32>(1.0, 0.0, 0.0));
    if dot(u, u) < 0.1 {
        u = cross(m, vec3<f32>(0.0, 1.0, 0.0));
    }
    u = normalize(u) * half;
    let v = cross(m, u);
    wall_quad = array<vec3<f32>, 4>(-u - v, u - v, u + v, v - u);
}

// Polyhedron s at x (orientation q, relative to the walls' origin) against a plane, quad or
// cylinder wall entry; results relative to the walls' origin.
fn volume_wall(s: u32, q: vec4<f32>, x: vec3<f32>, w: array<vec4<f32>, WALL_ENTRY_WORDS>) -> VolumeHit {
    let h = shape_head(s);
    let rb = h.radius;
    let eps = 1e-6 * rb;
    vc_sa = s;
    vc_r = quat_matrix(q);
    vc_out_q = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    vc_tau = CORNER_SMOOTHING * rb;
    vc_density_a = shape_edge_density(s);
    vc_density_b = vc_density_a;
    vc_quad = false;
    var origin: vec3<f32>;
    var push_term = vec3<f32>(0.0);
    var faces = 1u;
    switch u32(w[0].x) {
        case WALL_PLANE: {
            let normal = w[5].xyz;
            let height = dot(normal, x - w[1].xyz);
            if height >= rb {
                return no_volume_hit();
            }
            origin = x - normal * height;
            vc_kind = VC_PLANES;
            vc_planes_b[0] = vec4<f32>(normal, 0.0);
            vc_count_b = 1u;
            wall_square(normal, 2.0 * rb);
        }
        case WALL_QUAD: {
            let normal = w[5].xyz;
            let height = dot(normal, x - w[1].xyz);
            if abs(height) >= rb || (w[0].z == 0.0 && height <= 0.0) {
                return no_volume_hit();
            }
            let m = select(-normal, normal, height > 0.0);
            origin = x - m * abs(height);
            vc_kind = VC_PLANES;
            vc_quad = true;
            var middle = vec3<f32>(0.0);
            for (var k = 0u; k < 4u; k++) {
                wall_quad[k] = w[1u + k].xyz - origin;
                middle += 0.25 * wall_quad[k];
            }
            vc_planes_b[0] = vec4<f32>(m, dot(m, wall_quad[0]));
            for (var k = 0u; k < 4u; k++) {
                let a = wall_quad[k];
                var side = normalize(cross(wall_quad[(k + 1u) % 4u] - a, m));
                if dot(side, middle - a) > 0.0 {
                    side = -side;
                }
                vc_planes_b[1u + k] = vec4<f32>(side, dot(side, a));
            }
            vc_count_b = 5u;
            faces = 5u;
        }
        case WALL_CYLINDER: {
            let point = w[1].xyz;
            let axis = w[2].xyz;
            let radius = w[3].x;
            let inside = w[0].z != 0.0;
            let rel = x - point;
            let along = dot(rel, axis);
            if along < 0.0 || along > w[3].y {
                return no_volume_hit();
            }
            let radial = rel - axis * along;
            let rho = length(radial);
            if rho < 1e-6 * radius || (inside && rho + rb <= radius) || (!inside && rho - rb >= radius) {
                return no_volume_hit();
            }
            let out = radial / rho;
            let m = select(out, -out, inside);
            origin = point + axis * along + out * radius;
            vc_kind = VC_CYLINDER;
            vc_cyl_point = point - origin;
            vc_cyl_axis = axis;
            vc_cyl_radius = radius;
            vc_cyl_inside = inside;
            vc_planes_b[0] = vec4<f32>(m, 0.0);
            vc_count_b = 1u;
            wall_square(m, 2.0 * rb);
            push_term = cross(axis, radial) / (rho * rho);
        }
        default: {
            return no_volume_hit();
        }
    }
    vc_t = x - origin;
    vc_out_shift = origin;
    volume_load_planes(h, vc_r, vc_t, true);
    volume_reset();
    volume_clip_a(eps);
    for (var g = 0u; g < faces; g++) {
        let fn_ = wall_load_face(g, 2.0 * rb);
        volume_clip_b_face(4u, fn_, eps);
    }
    var push = vol_area;
    if vc_kind == VC_CYLINDER {
        // ∂V/∂φ of the tangent plane's azimuth: the overlap's moment about the axis.
        let t_u = dot(vol_moment - cross(vc_cyl_point, vol_area), vc_cyl_axis);
        push -= push_term * t_u;
    }
    var hit = volume_finish(push, vc_t, vec3<f32>(0.0), vol_depth);
    if !hit.hit && vc_kind == VC_CYLINDER {
        // Corners can cross the shell away from the centre's azimuth before anything crosses the
        // tangent plane: a contact of point loads alone (the caller drops it when none load).
        hit.hit = true;
        hit.normal = vc_planes_b[0].xyz;
    }
    hit.turn_b = vec3<f32>(0.0);
    return volume_out(hit);
}

// Smoothed depth of p inside A's (in_a) or B's planes (the smooth minimum over them with width
// vc_tau, tumble-geom's Region::penetration) and its gradient; depth ≤ 0 outside.
fn plane_penetration(p: vec3<f32>, in_a: bool) -> vec4<f32> {
    let count = select(vc_count_b, vc_count_a, in_a);
    var nearest = POLY_BIG;
    for (var f = 0u; f < count; f++) {
        let pl = select(vc_planes_b[f], vc_planes_a[f], in_a);
        let d = pl.w - dot(pl.xyz, p);
        if d <= 0.0 {
            return vec4<f32>(0.0);
        }
        nearest = min(nearest, d);
    }
    var sum = 0.0;
    var grad = vec3<f32>(0.0);
    for (var f = 0u; f < count; f++) {
        let pl = select(vc_planes_b[f], vc_planes_a[f], in_a);
        let w = exp(-(pl.w - dot(pl.xyz, p) - nearest) / vc_tau);
        sum += w;
        grad += w * pl.xyz;
    }
    return vec4<f32>(grad / sum, nearest - vc_tau * log(sum));
}

// A corner at p (frame) inside A's or B's planes: its load. `sign` −1 for B's corners.
fn corner_load(p: vec3<f32>, in_a: bool, sign: f32) {
    let c = plane_penetration(p, in_a);
    if c.w > 0.0 {
        point_load(quat_rotate(vc_out_q, p) + vc_out_shift, c.w, quat_rotate(vc_out_q, sign * c.xyz), 1.0);
    }
}

// Three Gauss points on s ∈ [s0, s1] of the edge p0 + s e, depth offset − m · p, weights
// w × half × |e| × density.
fn gauss_loads(p0: vec3<f32>, e: vec3<f32>, s0: f32, s1: f32, m: vec3<f32>, offset: f32, sign: f32, density: f32) {
    let mid = 0.5 * (s0 + s1);
    let half = 0.5 * (s1 - s0);
    let nodes = array<vec2<f32>, 3>(vec2<f32>(-0.7745966692, 5.0 / 9.0), vec2<f32>(0.0, 8.0 / 9.0), vec2<f32>(0.7745966692, 5.0 / 9.0));
    for (var k = 0u; k < 3u; k++) {
        let p = p0 + e * (mid + half * nodes[k].x);
        let depth = offset - dot(m, p);
        if depth > 0.0 {
            point_load(quat_rotate(vc_out_q, p) + vc_out_shift, depth, quat_rotate(vc_out_q, sign * m), nodes[k].y * half * length(e) * density);
        }
    }
}

// The part of the edge p0 → p1 (frame) inside A's or B's planes, as pieces on which one plane is
// the nearest (tumble-geom's segment_pieces), each by three Gauss points.
fn edge_loads(p0: vec3<f32>, p1: vec3<f32>, in_a: bool, sign: f32, density: f32) {
    let e = p1 - p0;
    let count = select(vc_count_b, vc_count_a, in_a);
    var lo = 0.0;
    var hi = 1.0;
    for (var f = 0u; f < count; f++) {
        let pl = select(vc_planes_b[f], vc_planes_a[f], in_a);
        let a = pl.w - dot(pl.xyz, p0);
        let b = dot(pl.xyz, e);
        if b > 0.0 {
            hi = min(hi, a / b);
        } else if b < 0.0 {
            lo = max(lo, a / b);
        } else if a <= 0.0 {
            return;
        }
    }
    if hi <= lo {
        return;
    }
    // The nearest plane at lo (ties: the one falling faster).
    var f = 0u;
    var best = POLY_BIG;
    var best_b = -POLY_BIG;
    for (var g = 0u; g < count; g++) {
        let pl = select(vc_planes_b[g], vc_planes_a[g], in_a);
        let a = pl.w - dot(pl.xyz, p0);
        let b = dot(pl.xyz, e);
        let h = a - lo * b;
        if h < best || (h == best && b > best_b) {
            best = h;
            best_b = b;
            f = g;
        }
    }
    var s = lo;
    for (var iter = 0u; iter <= count; iter++) {
        let pf = select(vc_planes_b[f], vc_planes_a[f], in_a);
        let af = pf.w - dot(pf.xyz, p0);
        let bf = dot(pf.xyz, e);
        var next = hi;
        var g_next = f;
        for (var g = 0u; g < count; g++) {
            let pl = select(vc_planes_b[g], vc_planes_a[g], in_a);
            let b = dot(pl.xyz, e);
            if b > bf {
                let x = (pl.w - dot(pl.xyz, p0) - af) / (b - bf);
                if x > s && x < next {
                    next = x;
                    g_next = g;
                }
            }
        }
        gauss_loads(p0, e, s, next, pf.xyz, pf.w, sign, density);
        if next >= hi || g_next == f {
            break;
        }
        s = next;
        f = g_next;
    }
}

// A point's depth beyond the true cylinder (drum) or within it (pipe), with its gradient.
fn cylinder_penetration(p: vec3<f32>) -> vec4<f32> {
    let r = p - vc_cyl_point;
    let across = r - vc_cyl_axis * dot(r, vc_cyl_axis);
    let len = length(across);
    if len <= 0.0 {
        return vec4<f32>(0.0);
    }
    let depth = select(vc_cyl_radius - len, len - vc_cyl_radius, vc_cyl_inside);
    return vec4<f32>(select(across / len, -across / len, vc_cyl_inside), depth);
}

// The edge p0 → p1 against the true cylinder as CYLINDER_EDGE_POINTS material points at the
// middles of equal parts (tumble-geom's Cylinder::penetrating_points: the depth is not linear
// along an edge here, and points fixed on the body keep the potential exact).
fn cylinder_edge_loads(p0: vec3<f32>, p1: vec3<f32>) {
    let n = f32(CYLINDER_EDGE_POINTS);
    let weight = length(p1 - p0) / n * vc_density_a;
    for (var k = 0u; k < CYLINDER_EDGE_POINTS; k++) {
        let p = p0 + (p1 - p0) * ((f32(k) + 0.5) / n);
        let c = cylinder_penetration(p);
        if c.w > 0.0 {
            point_load(p + vc_out_shift, c.w, c.xyz, weight);
        }
    }
}

// Every corner and edge point of the last volume_pair / volume_wall, through point_load.
fn volume_points() {
    let ha = shape_head(vc_sa);
    if vc_kind == VC_CYLINDER {
        for (var i = 0u; i < ha.nv; i++) {
            let p = vc_r * shape_vertex(ha, i) + vc_t;
            let c = cylinder_penetration(p);
            if c.w > 0.0 {
                point_load(p + vc_out_shift, c.w, c.xyz, 1.0);
            }
        }
        for (var e = 0u; e < ha.ne; e++) {
            let ed = shape_edge(ha, e);
            cylinder_edge_loads(vc_r * shape_vertex(ha, ed.x) + vc_t, vc_r * shape_vertex(ha, ed.y) + vc_t);
        }
        return;
    }
    for (var i = 0u; i < ha.nv; i++) {
        corner_load(vc_r * shape_vertex(ha, i) + vc_t, false, 1.0);
    }
    for (var e = 0u; e < ha.ne; e++) {
        let ed = shape_edge(ha, e);
        edge_loads(vc_r * shape_vertex(ha, ed.x) + vc_t, vc_r * shape_vertex(ha, ed.y) + vc_t, false, 1.0, vc_density_a);
    }
    if vc_kind == VC_SHAPE {
        let hb = shape_head(vc_sb);
        for (var i = 0u; i < hb.nv; i++) {
            corner_load(shape_vertex(hb, i) + vc_tb, true, -1.0);
        }
        for (var e = 0u; e < hb.ne; e++) {
            let ed = shape_edge(hb, e);
            edge_loads(shape_vertex(hb, ed.x) + vc_tb, shape_vertex(hb, ed.y) + vc_tb, true, -1.0, vc_density_b);
        }
    } else if vc_quad {
        for (var k = 0u; k < 4u; k++) {
            corner_load(wall_quad[k], true, -1.0);
            edge_loads(wall_quad[k], wall_quad[(k + 1u) % 4u], true, -1.0, vc_density_b);
        }
    }
}
