// Sphere against polyhedron (tumble-geom's sphere_polyhedron.rs in f32): the closest point
// on a face, an edge or a vertex, or the nearest face from inside. Needs polyhedra.wgsl.

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
