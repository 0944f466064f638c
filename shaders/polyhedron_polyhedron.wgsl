// Polyhedron against polyhedron (tumble-geom's polyhedron_polyhedron.rs in f32): separating
// axes over both bodies' faces and the Gauss-map-pruned edge pairs, minimum penetration, the
// incident face clipped by the reference face. Needs polyhedra.wgsl.

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
        let low = shape_min_dot(ha, m);
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
        let low = shape_min_dot(hb, n);
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
        let inc = incident_face(ha, m);
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
        let inc = incident_face(hb, n);
        let n_inc = load_face(hb, inc, mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(0.0), 1u);
        let deepest = shape_vertex(hb, shape_support(hb, -n));
        normal = -n;
        depth = -best_a;
        point = face_contact_point(n_ref, n, pl.w + dot(n, t), n_inc, depth, deepest);
    }
    return PolyHit(true, quat_rotate(qb, normal), depth, quat_rotate(qb, point), poly_spread);
}
