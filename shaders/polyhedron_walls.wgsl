// Polyhedron against walls (tumble-geom's polyhedron_plane.rs, polyhedron_quad.rs and
// polyhedron_cylinder.rs in f32), coordinates relative to one origin. Needs polyhedra.wgsl.

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
        if d > 0.0 && m < MANIFOLD_POINTS {
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

// Overlap along m of the quad (corners qc, body frame) over the polyhedron h: how far the
// polyhedron must move along m to clear it.
fn quad_overlap(h: ShapeHead, qc: array<vec3<f32>, 4>, m: vec3<f32>) -> f32 {
    var qmax = -POLY_BIG;
    for (var j = 0u; j < 4u; j++) {
        qmax = max(qmax, dot(qc[j], m));
    }
    return qmax - shape_min_dot(h, m);
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
    // Axis kinds: 0 quad face (its side in `face_sign`), 1 polyhedron face, 2 edge pair,
    // 3 an in-plane normal (one-sided quads).
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
    // Edge pairs, both orientations (kind 2, candidate c = 4 e + k); then, one-sided, the rim
    // of the allowed directions, the quad's plane, where the least overlap lies along an
    // in-plane normal of a quad edge or a polyhedron edge (kind 3).
    let pairs = 4u * h.ne;
    let rim = select(0u, 4u + h.ne, !two_sided);
    for (var c = 0u; c < pairs + rim; c++) {
        var a: vec3<f32>;
        var b: vec3<f32>;
        var kind = 2u;
        if c < pairs {
            let ed = shape_edge(h, c / 4u);
            a = shape_vertex(h, ed.y) - shape_vertex(h, ed.x);
            b = qc[(c % 4u + 1u) % 4u] - qc[c % 4u];
        } else {
            kind = 3u;
            a = qn;
            let w = c - pairs;
            if w < 4u {
                b = qc[(w + 1u) % 4u] - qc[w];
            } else {
                let ed = shape_edge(h, w - 4u);
                b = shape_vertex(h, ed.y) - shape_vertex(h, ed.x);
            }
        }
        let mm = cross(a, b);
        if dot(mm, mm) <= 1e-12 * dot(a, a) * dot(b, b) {
            continue;
        }
        let m0 = normalize(mm);
        for (var side = 0u; side < 2u; side++) {
            let m = select(-m0, m0, side == 0u);
            let depth = quad_overlap(h, qc, m);
            if depth <= 0.0 {
                return no_poly_hit();
            }
            if (two_sided || dot(m, qn) >= -1e-6) && depth < best_depth - tie {
                best_depth = depth;
                best_m = m;
                best_kind = kind;
                best_i = c / 4u;
                best_k = c % 4u;
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
        let inc = incident_face(h, n);
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
    } else if best_kind == 3u {
        point = shape_vertex(h, shape_support(h, -best_m)) + best_m * (0.5 * best_depth);
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
            if d > 0.0 && m < MANIFOLD_POINTS {
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

// A wall table entry (geometry.wgsl layout: w0 = (kind, material, flag, _), then points and
// directions); a kind this code does not know (prisms go as polyhedra) touches nothing.
fn polyhedron_wall(s: u32, q: vec4<f32>, x: vec3<f32>, w: array<vec4<f32>, WALL_ENTRY_WORDS>) -> PolyHit {
    switch u32(w[0].x) {
        case WALL_PLANE: {
            return polyhedron_plane(s, q, x, w[1].xyz, w[5].xyz);
        }
        case WALL_QUAD: {
            let corners = array<vec3<f32>, 4>(w[1].xyz, w[2].xyz, w[3].xyz, w[4].xyz);
            return polyhedron_quad(s, q, x, corners, w[5].xyz, w[0].z != 0.0);
        }
        case WALL_CYLINDER: {
            return polyhedron_cylinder(s, q, x, w[1].xyz, w[2].xyz, w[3].x, w[3].y, w[0].z != 0.0);
        }
        default: {
            return no_poly_hit();
        }
    }
}
