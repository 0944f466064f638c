// The contact pass's pairs and walls with a polyhedral particle (POLYHEDRA; forces.wgsl
// calls these): the narrow phase of polyhedra.wgsl and its siblings, the force laws of
// forces.wgsl with the volume-equivalent radius, twisting friction and rolling resistance.

fn shape_of(j: u32) -> u32 {
    return props[j].w >> SHAPE_SHIFT;
}

// Word i of the shape table, which follows the walls in `tables`.
fn shape_word(i: u32) -> vec4<f32> {
    return tables[params.shape_base + i];
}

// R* and overlap-ratio radius of particle j: the radius of the sphere of equal volume.
fn equivalent_radius(j: u32) -> f32 {
    let s = shape_of(j);
    if s == SPHERE_SHAPE {
        return pos[j].w;
    }
    return shape_inertia(s).w;
}

// n · I_w⁻¹ n of particle j: its inverse moment of inertia about the axis n.
fn inverse_inertia_about(j: u32, n: vec3<f32>) -> f32 {
    let s = shape_of(j);
    if s == SPHERE_SHAPE {
        return omega[j].w;
    }
    let nb = quat_rotate(quat_conj(orient[j]), n);
    return dot(nb * nb, shape_inertia(s).xyz * vel[j].w);
}

// Coulomb friction against the relative spin about the normal on a contact patch of
// radius `spread` (tumble-cpu's twisting_torque): μ |F_n| r̄, capped so that it never
// reverses the relative spin within a step. One-point contacts (spread 0) have none.
fn twisting_torque(spread: f32, friction: f32, normal_force: f32, n: vec3<f32>, spin_rel: vec3<f32>, inv_inertia_sum: f32) -> vec3<f32> {
    if spread <= 0.0 || friction == 0.0 {
        return vec3<f32>(0.0);
    }
    return rolling_torque(friction, spread, normal_force, n * dot(spin_rel, n), inv_inertia_sum);
}

// A pair with at least one polyhedron (a holding the lower id, d = x_a − x_b): one
// contact (normal, depth, point) from polyhedra.wgsl, the force laws of spheres with
// m* and R* from the volume-equivalent radii, the torque of the whole force about
// each centre, twisting friction on the patch, and rolling resistance.
fn polyhedron_pair(a: u32, b: u32, d: vec3<f32>) -> PairOut {
    var out = PairOut(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, -1.0, vec4<f32>(0.0));
    let sa = shape_of(a);
    let sb = shape_of(b);
    var hit: PolyHit;
    // The contact point relative to x_b.
    var point = vec3<f32>(0.0);
    if sa != SPHERE_SHAPE && sb != SPHERE_SHAPE {
        hit = polyhedron_polyhedron(sa, orient[a], sb, orient[b], d);
        point = hit.point;
    } else if sa == SPHERE_SHAPE {
        hit = sphere_polyhedron(pos[a].w, sb, orient[b], d);
        point = hit.point;
    } else {
        hit = sphere_polyhedron(pos[b].w, sa, orient[a], -d);
        hit.normal = -hit.normal;
        point = hit.point + d;
    }
    if !hit.hit {
        return out;
    }
    let n = hit.normal;
    let arm_b = point;
    let arm_a = point - d;
    let spin_a = seen_spin(a);
    let spin_b = seen_spin(b);
    let v_rel = seen_velocity(a) + cross(spin_a, arm_a) - seen_velocity(b) - cross(spin_b, arm_b);
    let m_star = 1.0 / (vel[a].w + vel[b].w);
    let ra = equivalent_radius(a);
    let rb = equivalent_radius(b);
    let r_star = ra * rb / (ra + rb);
    var old_spring = vec4<f32>(0.0);
    if HISTORY {
        old_spring = find_spring(props[a].z, props[b].z);
    }
    let pair = props[a].y * params.materials + props[b].y;
    let f = contact_force(pair, n, hit.depth, 0.0, v_rel, m_star, r_star, old_spring);
    out.force = f.force;
    out.spring = f.spring;
    out.torque_a = cross(arm_a, f.force);
    out.torque_b = cross(arm_b, -f.force);
    let spin = spin_a - spin_b;
    let inv_n = inverse_inertia_about(a, n) + inverse_inertia_about(b, n);
    let twist = twisting_torque(hit.spread, tables[PAIR_ENTRY_WORDS * pair + 1u].y, f.normal, n, spin, inv_n);
    out.torque_a += twist;
    out.torque_b -= twist;
    out.dissipation = f.dissipation - dot(twist, spin);
    if ROLLING {
        let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r_star, f.normal, spin, omega[a].w + omega[b].w);
        out.torque_a += roll;
        out.torque_b -= roll;
        out.dissipation -= dot(roll, spin);
    }
    out.elastic = f.elastic;
    out.ratio = hit.depth / min(ra, rb);
    return out;
}

// A polyhedral particle i against wall k (entry at `base`): the force, the torque about
// the centre with twisting friction and rolling resistance, into the sum (tumble-cpu's
// polyhedron_wall). Returns the power the wall delivers (MOVING): F · v_wall at the contact
// point plus the twisting and rolling couples times the wall's spin.
fn polyhedron_wall_contact(s: ptr<function, Sum>, i: u32, k: u32, base: u32) -> f32 {
    let x = pos[i].xyz;
    let shape = shape_of(i);
    var hit = no_poly_hit();
    switch wall_kind(base) {
        case WALL_PRISM: {
            if PRISMS {
                hit = polyhedron_prism(shape, orient[i], x, base);
            }
        }
        default: {
            let entry = array<vec4<f32>, WALL_ENTRY_WORDS>(tables[base], tables[base + 1u], tables[base + 2u], tables[base + 3u], tables[base + 4u], tables[base + 5u]);
            hit = polyhedron_wall(shape, orient[i], x, entry);
        }
    }
    if !hit.hit {
        return 0.0;
    }
    let arm = hit.point - x;
    let w = seen_spin(i);
    var v_wall = vec3<f32>(0.0);
    var wall_w = vec3<f32>(0.0);
    if MOVING {
        v_wall = wall_velocity(base, hit.point);
        wall_w = wall_spin(base);
    }
    let v_rel = seen_velocity(i) + cross(w, arm) - v_wall;
    let pair = props[i].y * params.materials + wall_material(base);
    let r = equivalent_radius(i);
    var old_spring = vec4<f32>(0.0);
    if HISTORY {
        old_spring = find_spring(props[i].z, WALL_KEY | k);
    }
    let f = contact_force(pair, hit.normal, hit.depth, 0.0, v_rel, alpha[i].w, r, old_spring);
    if HISTORY {
        (*s).springs = keep_spring(props[i].z, (*s).springs, WALL_KEY | k, f.spring);
    }
    // Twisting friction and rolling resistance act against the spin relative to the wall.
    let spin = w - wall_w;
    let twist = twisting_torque(hit.spread, tables[PAIR_ENTRY_WORDS * pair + 1u].y, f.normal, hit.normal, spin, inverse_inertia_about(i, hit.normal));
    (*s).force += f.force;
    (*s).torque += cross(arm, f.force) + twist;
    (*s).elastic += f.elastic;
    (*s).dissipation += f.dissipation - dot(twist, spin);
    var power = dot(f.force, v_wall) + dot(twist, wall_w);
    if ROLLING {
        // The volume-equivalent radius, as on the CPU.
        let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r, f.normal, spin, omega[i].w);
        (*s).torque += roll;
        (*s).dissipation -= dot(roll, spin);
        power += dot(roll, wall_w);
    }
    (*s).contacts += 1u;
    (*s).ratio = max((*s).ratio, hit.depth / r);
    return power;
}
