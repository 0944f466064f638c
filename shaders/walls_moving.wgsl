// Moving world geometry (prepended to forces.wgsl after geometry.wgsl and
// history.wgsl): wall velocities, per-group wall power and work, and lifter
// bars (convex prisms, tumble-geom's sphere_prism.rs in f32; polyhedral particles meet
// a bar's hull through the polyhedron–polyhedron narrow phase).
//
// The host writes every wall's pose at the step's force time into the wall
// table before each contact pass (Wall::shape_at in f64, then f32 relative to
// the domain's centre), so the proximity code only ever sees the current pose.
//
// Wall table extras: w0.w of a wall's entry is the index of its first extra vec4.
//   with MOVING, every wall (WALL_MOTION_WORDS): e0 = (angular velocity ω, wall group),
//                            e1 = (velocity of the wall material at the domain's centre, 0);
//                            a static wall has zeros.
//   prism (WALL_PRISM), after the motion entries when MOVING:
//     p0 = (centre of the enclosing sphere, its radius), p1 = (drum axis point, inner radius),
//     p2 = (drum axis, 0) (PRISM_HEAD_WORDS), then per face (PRISM_FACES): 4 corners and the
//     outward normal (PRISM_FACE_WORDS); with POLYHEDRA, from PRISM_HULL on, the bar's hull
//     (prisms.rs): (its centre, its shape index), its orientation quaternion (x, y, z, w), in
//     the pose of the contact pass.
//
// Wall loads (WALLS): per particle ORIGINAL id and wall group, two vec4 of the last pass: the
// force on the wall (xyz) and the power F_on_particle · v_wall (+ Ω_wall · rolling couple,
// + Ω_wall · twisting couple for polyhedra; w), then the torque on the wall about the device's
// origin (xyz); with MOVING the work Σ power Δt as a Kahan pair. Each invocation writes only
// its own id's entries (`wall_load`, `wall_work`); the reduction sums them in id order.

fn wall_extras(base: u32) -> u32 {
    return u32(tables[base].w);
}

// Velocity of the wall material at x (relative to the domain's centre) for a contact with
// normal n: ω × x + v(centre); a conveyor (w of the second word set) moves along itself only,
// so the part of its surface velocity along n is dropped (tumble_scene's Wall::contact_velocity).
fn wall_velocity(base: u32, x: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let e = wall_extras(base);
    let v = cross(tables[e].xyz, x) + tables[e + 1u].xyz;
    if tables[e + 1u].w > 0.5 {
        return v - n * dot(v, n);
    }
    return v;
}

// The wall's angular velocity (zero unless it rotates).
fn wall_spin(base: u32) -> vec3<f32> {
    return tables[wall_extras(base)].xyz;
}

// The wall's group (w5.w of its entry, every kind of wall).
fn wall_group(base: u32) -> u32 {
    return u32(tables[base + 5u].w);
}

// Number of wall groups.
fn wall_groups() -> u32 {
    return params.wall_groups;
}

// Kahan summation: (sum, compensation) plus x.
fn work_add(acc_in: vec2<f32>, x: f32) -> vec2<f32> {
    let y = x - acc_in.y;
    let t = acc_in.x + y;
    return vec2<f32>(t, (t - acc_in.x) - y);
}

// Books one group's load from slot i: `force` and `torque` (about i's centre) are what the
// group's surfaces did to the particle; the wall takes the reaction, −F and −(x × F + τ) about
// the device's origin. The work is added on committed passes (the host clears the t = 0 pass's).
fn book_wall_load(i: u32, group: u32, power: f32, force: vec3<f32>, torque: vec3<f32>) {
    let k = props[i].z * wall_groups() + group;
    wall_load[2u * k] = vec4<f32>(-force, power);
    wall_load[2u * k + 1u] = vec4<f32>(-(cross(pos[i].xyz, force) + torque), 0.0);
    if MOVING && power != 0.0 {
        wall_work[k] = work_add(wall_work[k], power * params.dt);
    }
}

fn prism_face_inside(f: u32, n: vec3<f32>, foot: vec3<f32>) -> bool {
    var inside = true;
    for (var k = 0u; k < 4u; k++) {
        let p = tables[f + k].xyz;
        let q = tables[f + (k + 1u) % 4u].xyz;
        inside = inside && dot(cross(q - p, foot - p), n) >= 0.0;
    }
    return inside;
}

// Closest point of face f (4 corners from index f, normal at f + 4) to c.
fn prism_face_closest(f: u32, c: vec3<f32>) -> vec3<f32> {
    let n = tables[f + 4u].xyz;
    let foot = c - n * dot(n, c - tables[f].xyz);
    if prism_face_inside(f, n, foot) {
        return foot;
    }
    var closest = closest_on_segment(tables[f].xyz, tables[f + 1u].xyz, c);
    var best = dot(closest - c, closest - c);
    for (var k = 1u; k < 4u; k++) {
        let q = closest_on_segment(tables[f + k].xyz, tables[f + (k + 1u) % 4u].xyz, c);
        let d2 = dot(q - c, q - c);
        if d2 < best {
            best = d2;
            closest = q;
        }
    }
    return closest;
}

// Sphere–prism proximity: one contact per bar (face, edge or corner region; a centre
// inside leaves by the face of least penetration). Same convention as the CPU.
fn prism_proximity(base: u32, centre: vec3<f32>, radius: f32, reach: f32) -> Proximity {
    let p = prism_data(base);
    let range = radius + reach;
    let bound = tables[p].w + range;
    let dc = centre - tables[p].xyz;
    if dot(dc, dc) > bound * bound {
        return no_proximity();
    }
    let axis = tables[p + 2u].xyz;
    let rel = centre - tables[p + 1u].xyz;
    let radial = rel - axis * dot(rel, axis);
    let near = tables[p + 1u].w - range;
    if near > 0.0 && dot(radial, radial) < near * near {
        return no_proximity();
    }
    var h: array<f32, PRISM_FACES>;
    var deepest = 0u;
    var outside = false;
    for (var k = 0u; k < PRISM_FACES; k++) {
        let f = p + PRISM_HEAD_WORDS + PRISM_FACE_WORDS * k;
        h[k] = dot(tables[f + 4u].xyz, centre - tables[f].xyz);
        if h[k] >= range {
            return no_proximity();
        }
        outside = outside || h[k] > 0.0;
        if h[k] >= h[deepest] {
            deepest = k;
        }
    }
    if !outside {
        // Centre inside: leave by the nearest face (the least penetration).
        let n = tables[p + PRISM_HEAD_WORDS + PRISM_FACE_WORDS * deepest + 4u].xyz;
        let overlap = radius - h[deepest];
        return Proximity(true, n, overlap, centre - n * (h[deepest] + 0.5 * overlap));
    }
    // Outside: the closest point lies on a face the centre is in front of.
    var best = -1.0;
    var closest = vec3<f32>(0.0);
    var normal = vec3<f32>(0.0);
    for (var k = 0u; k < PRISM_FACES; k++) {
        if h[k] <= 0.0 {
            continue;
        }
        let f = p + PRISM_HEAD_WORDS + PRISM_FACE_WORDS * k;
        let q = prism_face_closest(f, centre);
        let d2 = dot(centre - q, centre - q);
        if best < 0.0 || d2 < best {
            best = d2;
            closest = q;
            normal = tables[f + 4u].xyz;
        }
    }
    return contact_from_closest(centre, radius, reach, closest, normal);
}

fn prism_data(base: u32) -> u32 {
    var e = wall_extras(base);
    if MOVING {
        e += WALL_MOTION_WORDS;
    }
    return e;
}

// Polyhedron s at x (orientation q) against the bar at `base`: its hull, a table shape in
// the pass's pose, through the polyhedron–polyhedron narrow phase (tumble-geom's
// Prism::polyhedron_contact). Normal from the bar to the polyhedron; the point relative to
// the walls' origin.
fn polyhedron_prism(s: u32, q: vec4<f32>, x: vec3<f32>, base: u32) -> PolyHit {
    let hull = prism_data(base) + PRISM_HULL;
    let centre = tables[hull];
    var hit = polyhedron_polyhedron(s, q, u32(centre.w), tables[hull + 1u], x - centre.xyz);
    hit.point += centre.xyz;
    return hit;
}
