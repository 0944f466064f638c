// Overlap-volume contacts in f32 (tumble-geom's overlap_volume.rs and volume_contact.rs): the
// overlap of polyhedron A with polyhedron B or a wall's solid, its volume V, the area vector S
// and moment M of B's faces inside A (V's derivatives: the force on A per unit w'(V) is S, the
// torque about x_A is M − x_A × S), and the corners of each body inside the other with their
// smoothed depths. Needs polyhedra.wgsl (the shape table, poly_a and poly_b).
//
// The boundary of A ∩ B is A's faces clipped by B's planes and B's faces clipped by A's planes;
// both are accumulated relative to an origin near the overlap (the separating-axis contact point
// for pairs, the foot of A's centre on the surface for walls), so the sums stay of the size of V.
// A face lying in a plane of the other body with the same outward normal counts half. A wall's
// solid: a plane's half-space (its face a square of half-size 2 R_A about the origin), a quad's
// semi-infinite prism (the quad and four side rectangles 2 R_A deep), a cylinder's half-space
// behind its tangent plane at the azimuth of A's centre, with the azimuth term in the push.
//
// After a call, poly_a[k] = (corner point, depth) and poly_b[k] = (depth gradient, 1 for a corner
// of A, 0 for one of B) for k < hit.corners, points and vectors in the world orientation relative
// to the caller's origin (x_B for pairs, the walls' origin for walls). At most MANIFOLD_POINTS
// corners are kept (the deepest overlaps of large shapes could have more).

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
    corners: u32,
}

fn no_volume_hit() -> VolumeHit {
    return VolumeHit(false, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, 0u);
}

// (contact area, corners of the largest face) of shape s.
fn shape_contact(s: u32) -> vec2<f32> {
    return shape_word(SHAPE_HEADER_WORDS * s + 3u).xy;
}

// The running sums: volume, ∫x dV, S, M (relative to the origin), deepest point below plane 0.
var<private> vol_volume: f32;
var<private> vol_first: vec3<f32>;
var<private> vol_area: vec3<f32>;
var<private> vol_moment: vec3<f32>;
var<private> vol_depth: f32;
// A wall's solid: its planes (m, offset) relative to the origin, its faces' corners.
var<private> wall_planes: array<vec4<f32>, 5>;
var<private> wall_quad: array<vec3<f32>, 4>;

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

// The plane of face f of shape h mapped by p ↦ r p + t: (m, offset).
fn volume_face_plane(h: ShapeHead, f: u32, r: mat3x3<f32>, t: vec3<f32>) -> vec4<f32> {
    let pl = shape_face(h, f);
    let m = r * pl.xyz;
    return vec4<f32>(m, pl.w + dot(m, t));
}

// Smoothed depth of p inside the shape h mapped by (r, t) (the smooth minimum over its planes
// with width tau, tumble-geom's Region::penetration) and its gradient; depth ≤ 0 outside.
fn shape_penetration(h: ShapeHead, r: mat3x3<f32>, t: vec3<f32>, p: vec3<f32>, tau: f32) -> vec4<f32> {
    var nearest = POLY_BIG;
    for (var f = 0u; f < h.nf; f++) {
        let pl = volume_face_plane(h, f, r, t);
        let d = pl.w - dot(pl.xyz, p);
        if d <= 0.0 {
            return vec4<f32>(0.0);
        }
        nearest = min(nearest, d);
    }
    var sum = 0.0;
    var grad = vec3<f32>(0.0);
    for (var f = 0u; f < h.nf; f++) {
        let pl = volume_face_plane(h, f, r, t);
        let w = exp(-(pl.w - dot(pl.xyz, p) - nearest) / tau);
        sum += w;
        grad += w * pl.xyz;
    }
    return vec4<f32>(grad / sum, nearest - tau * log(sum));
}

// The same for the wall's planes (count n).
fn wall_penetration(n: u32, p: vec3<f32>, tau: f32) -> vec4<f32> {
    var nearest = POLY_BIG;
    for (var k = 0u; k < n; k++) {
        let d = wall_planes[k].w - dot(wall_planes[k].xyz, p);
        if d <= 0.0 {
            return vec4<f32>(0.0);
        }
        nearest = min(nearest, d);
    }
    var sum = 0.0;
    var grad = vec3<f32>(0.0);
    for (var k = 0u; k < n; k++) {
        let w = exp(-(wall_planes[k].w - dot(wall_planes[k].xyz, p) - nearest) / tau);
        sum += w;
        grad += w * wall_planes[k].xyz;
    }
    return vec4<f32>(grad / sum, nearest - tau * log(sum));
}

// The hit from the sums: push (S plus any azimuth term), turns about the centres xa, xb (relative
// to the origin), the action point.
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

// Polyhedron sa (orientation qa) against polyhedron sb (qb), d = x_a − x_b; results relative to
// x_b in the world orientation.
fn volume_pair(sa: u32, qa: vec4<f32>, sb: u32, qb: vec4<f32>, d: vec3<f32>) -> VolumeHit {
    let gate = polyhedron_polyhedron(sa, qa, sb, qb, d);
    if !gate.hit {
        return no_volume_hit();
    }
    let ha = shape_head(sa);
    let hb = shape_head(sb);
    // B's body frame, origin at the gate's contact point: A's points are r p + t.
    let qbi = quat_conj(qb);
    let o = quat_rotate(qbi, gate.point);
    let r = quat_matrix(quat_mul(qbi, qa));
    let t = quat_rotate(qbi, d) - o;
    let eye = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    let eps = 1e-6 * max(ha.radius, hb.radius);
    volume_reset();
    for (var f = 0u; f < ha.nf; f++) {
        let face = volume_load_face(ha, f, r, t);
        var n = u32(face.w);
        var shared_ = 0u;
        for (var g = 0u; g < hb.nf && n > 0u; g++) {
            let pl = volume_face_plane(hb, g, eye, -o);
            let c = volume_clip(n, face.xyz, pl.xyz, pl.w, eps);
            n = c.x;
            shared_ = max(shared_, c.y);
        }
        if n > 0u {
            volume_add(n, select(1.0, 0.5, shared_ != 0u), 0.0);
        }
    }
    for (var g = 0u; g < hb.nf; g++) {
        let face = volume_load_face(hb, g, eye, -o);
        var n = u32(face.w);
        var shared_ = 0u;
        for (var f = 0u; f < ha.nf && n > 0u; f++) {
            let pl = volume_face_plane(ha, f, r, t);
            let c = volume_clip(n, face.xyz, pl.xyz, pl.w, eps);
            n = c.x;
            shared_ = max(shared_, c.y);
        }
        if n > 0u {
            let w = select(1.0, 0.5, shared_ != 0u);
            volume_add(n, w, w);
        }
    }
    var hit = volume_finish(vol_area, t, -o, gate.depth);
    if !hit.hit {
        return hit;
    }
    // Corners of A inside B and of B inside A.
    let tau = CORNER_SMOOTHING * min(ha.radius, hb.radius);
    var m = 0u;
    for (var i = 0u; i < ha.nv; i++) {
        let p = r * shape_vertex(ha, i) + t;
        let c = shape_penetration(hb, eye, -o, p, tau);
        if c.w > 0.0 && m < MANIFOLD_POINTS {
            poly_a[m] = vec4<f32>(quat_rotate(qb, p + o), c.w);
            poly_b[m] = vec4<f32>(quat_rotate(qb, c.xyz), 1.0);
            m++;
        }
    }
    for (var i = 0u; i < hb.nv; i++) {
        let p = shape_vertex(hb, i) - o;
        let c = shape_penetration(ha, r, t, p, tau);
        if c.w > 0.0 && m < MANIFOLD_POINTS {
            poly_a[m] = vec4<f32>(quat_rotate(qb, p + o), c.w);
            poly_b[m] = vec4<f32>(quat_rotate(qb, -c.xyz), 0.0);
            m++;
        }
    }
    hit.corners = m;
    // To the world orientation, relative to x_b.
    hit.push = quat_rotate(qb, hit.push);
    hit.turn_a = quat_rotate(qb, hit.turn_a);
    hit.turn_b = quat_rotate(qb, hit.turn_b);
    hit.normal = quat_rotate(qb, hit.normal);
    hit.point = quat_rotate(qb, hit.point + o);
    return hit;
}

// Clips A's faces (shape h, orientation q, centre x relative to the origin) by the wall's
// `count` planes and the wall's faces (`faces` of them, loaded by wall_load_face) by A's planes.
fn volume_wall_sums(h: ShapeHead, q: vec4<f32>, x: vec3<f32>, count: u32, faces: u32, depth_behind: f32, eps: f32) {
    let r = quat_matrix(q);
    volume_reset();
    for (var f = 0u; f < h.nf; f++) {
        let face = volume_load_face(h, f, r, x);
        var n = u32(face.w);
        var shared_ = 0u;
        for (var g = 0u; g < count && n > 0u; g++) {
            let c = volume_clip(n, face.xyz, wall_planes[g].xyz, wall_planes[g].w, eps);
            n = c.x;
            shared_ = max(shared_, c.y);
        }
        if n > 0u {
            for (var k = 0u; k < n; k++) {
                vol_depth = max(vol_depth, wall_planes[0].w - dot(wall_planes[0].xyz, poly_a[k].xyz));
            }
            volume_add(n, select(1.0, 0.5, shared_ != 0u), 0.0);
        }
    }
    for (var g = 0u; g < faces; g++) {
        let fn_ = wall_load_face(g, depth_behind);
        var n = 4u;
        var shared_ = 0u;
        for (var f = 0u; f < h.nf && n > 0u; f++) {
            let pl = volume_face_plane(h, f, r, x);
            let c = volume_clip(n, fn_, pl.xyz, pl.w, eps);
            n = c.x;
            shared_ = max(shared_, c.y);
        }
        if n > 0u {
            let w = select(1.0, 0.5, shared_ != 0u);
            volume_add(n, w, w);
        }
    }
}

// Face g of the wall's solid into poly_a, counter-clockwise about its outward normal (returned):
// face 0 the quad (wall_quad), faces 1–4 its sides, `depth` deep behind it.
fn wall_load_face(g: u32, depth: f32) -> vec3<f32> {
    let m = wall_planes[g].xyz;
    var p: array<vec3<f32>, 4>;
    if g == 0u {
        p = wall_quad;
    } else {
        let a = wall_quad[g - 1u];
        let b = wall_quad[g % 4u];
        let back = wall_planes[0].xyz * depth;
        p = array<vec3<f32>, 4>(a, b, b - back, a - back);
    }
    let flip = dot(cross(p[1] - p[0], p[2] - p[0]), m) < 0.0;
    for (var k = 0u; k < 4u; k++) {
        poly_a[k] = vec4<f32>(select(p[k], p[3u - k], flip), 0.0);
    }
    return m;
}

// The corners of A (shape h at x relative to the origin) inside the wall's `count` planes, and
// the wall's `quad_corners` corners inside A; from slot m on. Returns the new count.
fn wall_corners(h: ShapeHead, q: vec4<f32>, x: vec3<f32>, count: u32, quad_corners: u32, origin: vec3<f32>, tau: f32) -> u32 {
    let r = quat_matrix(q);
    var m = 0u;
    for (var i = 0u; i < h.nv; i++) {
        let p = r * shape_vertex(h, i) + x;
        let c = wall_penetration(count, p, tau);
        if c.w > 0.0 && m < MANIFOLD_POINTS {
            poly_a[m] = vec4<f32>(p + origin, c.w);
            poly_b[m] = vec4<f32>(c.xyz, 1.0);
            m++;
        }
    }
    for (var k = 0u; k < quad_corners; k++) {
        let c = shape_penetration(h, r, x, wall_quad[k], tau);
        if c.w > 0.0 && m < MANIFOLD_POINTS {
            poly_a[m] = vec4<f32>(wall_quad[k] + origin, c.w);
            poly_b[m] = vec4<f32>(-c.xyz, 0.0);
            m++;
        }
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
    let tau = CORNER_SMOOTHING * rb;
    switch u32(w[0].x) {
        case WALL_PLANE: {
            let normal = w[5].xyz;
            let height = dot(normal, x - w[1].xyz);
            if height >= rb {
                return no_volume_hit();
            }
            let origin = x - normal * height;
            wall_planes[0] = vec4<f32>(normal, 0.0);
            wall_square(normal, 2.0 * rb);
            volume_wall_sums(h, q, x - origin, 1u, 1u, 0.0, eps);
            var hit = volume_finish(vol_area, x - origin, vec3<f32>(0.0), vol_depth);
            if hit.hit {
                hit.corners = wall_corners(h, q, x - origin, 1u, 0u, origin, tau);
                hit.point += origin;
                hit.turn_b = vec3<f32>(0.0);
            }
            return hit;
        }
        case WALL_QUAD: {
            let normal = w[5].xyz;
            let height = dot(normal, x - w[1].xyz);
            if abs(height) >= rb || (w[0].z == 0.0 && height <= 0.0) {
                return no_volume_hit();
            }
            let m = select(-normal, normal, height > 0.0);
            let origin = x - m * abs(height);
            var middle = vec3<f32>(0.0);
            for (var k = 0u; k < 4u; k++) {
                wall_quad[k] = w[1u + k].xyz - origin;
                middle += 0.25 * wall_quad[k];
            }
            wall_planes[0] = vec4<f32>(m, dot(m, wall_quad[0]));
            for (var k = 0u; k < 4u; k++) {
                let a = wall_quad[k];
                var side = normalize(cross(wall_quad[(k + 1u) % 4u] - a, m));
                if dot(side, middle - a) > 0.0 {
                    side = -side;
                }
                wall_planes[1u + k] = vec4<f32>(side, dot(side, a));
            }
            volume_wall_sums(h, q, x - origin, 5u, 5u, 2.0 * rb, eps);
            var hit = volume_finish(vol_area, x - origin, vec3<f32>(0.0), vol_depth);
            if hit.hit {
                hit.corners = wall_corners(h, q, x - origin, 5u, 4u, origin, tau);
                hit.point += origin;
                hit.turn_b = vec3<f32>(0.0);
            }
            return hit;
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
            let origin = point + axis * along + out * radius;
            wall_planes[0] = vec4<f32>(m, 0.0);
            wall_square(m, 2.0 * rb);
            volume_wall_sums(h, q, x - origin, 1u, 1u, 0.0, eps);
            // ∂V/∂φ of the tangent plane's azimuth: the overlap's moment about the axis.
            let t_u = dot(vol_moment - cross(point - origin, vol_area), axis);
            let push = vol_area - cross(axis, radial) * (t_u / (rho * rho));
            var hit = volume_finish(push, x - origin, vec3<f32>(0.0), vol_depth);
            if hit.hit {
                // Corners against the true cylinder.
                let r = quat_matrix(q);
                var c = 0u;
                for (var i = 0u; i < h.nv; i++) {
                    let p = r * shape_vertex(h, i) + x;
                    let across = (p - point) - axis * dot(p - point, axis);
                    let len = length(across);
                    let depth = select(radius - len, len - radius, inside);
                    if depth > 0.0 && len > 0.0 && c < MANIFOLD_POINTS {
                        poly_a[c] = vec4<f32>(p, depth);
                        poly_b[c] = vec4<f32>(select(across / len, -across / len, inside), 1.0);
                        c++;
                    }
                }
                hit.corners = c;
                hit.point += origin;
                hit.turn_b = vec3<f32>(0.0);
            }
            return hit;
        }
        default: {
            return no_volume_hit();
        }
    }
}
