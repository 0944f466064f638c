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
    if VOLUME && shape_of(a) != SPHERE_SHAPE && shape_of(b) != SPHERE_SHAPE {
        return volume_polyhedron_pair(a, b, d);
    }
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
        // Rolling only: the spin about the normal is twisting friction's (two caps on one axis could reverse it).
        let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r_star, f.normal, spin - n * dot(spin, n), omega[a].w + omega[b].w);
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
    if VOLUME {
        return volume_wall_contact(s, i, k, base);
    }
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
        v_wall = wall_velocity(base, hit.point, hit.normal);
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
        let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r, f.normal, spin - hit.normal * dot(spin, hit.normal), omega[i].w);
        (*s).torque += roll;
        (*s).dissipation -= dot(roll, spin);
        power += dot(roll, wall_w);
    }
    (*s).contacts += 1u;
    (*s).ratio = max((*s).ratio, hit.depth / r);
    return power;
}

// ---- The overlap-volume model (VOLUME; tumble-cpu's volume_force) ----

struct VolumeForce {
    force: vec3<f32>,
    torque_a: vec3<f32>,
    torque_b: vec3<f32>,
    // max(F_n, 0) along the normal: the friction capacity, the rolling and twisting torques'.
    normal: f32,
    elastic: f32,
    dissipation: f32,
    spring: vec4<f32>,
}

// Where volume_points' loads go: the law of pair pl_pair at mass pl_mass, the bodies' rigid
// motions (velocity, spin, about which point), and the sums.
var<private> pl_pair: u32;
var<private> pl_mass: f32;
var<private> pl_r_star: f32;
var<private> pl_va: vec3<f32>;
var<private> pl_wa: vec3<f32>;
var<private> pl_xa: vec3<f32>;
var<private> pl_vb: vec3<f32>;
var<private> pl_wb: vec3<f32>;
var<private> pl_xb: vec3<f32>;
var<private> pl_force: vec3<f32>;
var<private> pl_torque_a: vec3<f32>;
var<private> pl_torque_b: vec3<f32>;
var<private> pl_elastic: f32;
var<private> pl_dissipation: f32;
// The loads' normal stiffness (for tangential laws timed by t_col) and the deepest load.
var<private> pl_stiffness: f32;
var<private> pl_deepest: f32;

// The velocity of A relative to B at p.
fn relative_velocity(p: vec3<f32>) -> vec3<f32> {
    return pl_va + cross(pl_wa, p - pl_xa) - pl_vb - cross(pl_wb, p - pl_xb);
}

// One corner or edge point of a volume contact: the law at its depth along its gradient, times its weight.
fn point_load(p: vec3<f32>, depth: f32, g: vec3<f32>, weight: f32) {
    let vn = dot(g, relative_velocity(p));
    let law = normal_law(pl_pair, depth, vn, pl_mass, pl_r_star);
    let pushed = weight * applied_normal(pl_pair, law);
    let f = g * pushed;
    pl_force += f;
    pl_torque_a += cross(p - pl_xa, f);
    pl_torque_b -= cross(p - pl_xb, f);
    pl_elastic += weight * law.z;
    pl_dissipation -= (pushed - weight * law.x) * vn;
    pl_stiffness += weight * law.w * dot(g, g);
    pl_deepest = max(pl_deepest, depth);
}

// The force of the last volume contact `hit` on body A, A moving rigidly with (va, wa) about xa
// and B with (vb, wb) about xb (a wall: its velocity at xb and its spin), all relative to the
// hit's origin: the normal law at δ_V = V / a_ref with the rate −V̇ / a_ref along the volume's
// gradient, each corner and edge point at its depth (volume_points), every part damped as the law
// at m* / weight; the tangential law at the contact point with the normal force's magnitude.
fn volume_force(pair: u32, hit: VolumeHit, a_ref: f32, weight: f32, va: vec3<f32>, wa: vec3<f32>, xa: vec3<f32>, vb: vec3<f32>, wb: vec3<f32>, xb: vec3<f32>, m_star: f32, r_star: f32, old_spring: vec4<f32>) -> VolumeForce {
    var out = VolumeForce(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, 0.0, vec4<f32>(0.0));
    pl_pair = pair;
    pl_mass = m_star / weight;
    pl_r_star = r_star;
    pl_va = va;
    pl_wa = wa;
    pl_xa = xa;
    pl_vb = vb;
    pl_wb = wb;
    pl_xb = xb;
    pl_force = vec3<f32>(0.0);
    pl_torque_a = vec3<f32>(0.0);
    pl_torque_b = vec3<f32>(0.0);
    pl_elastic = 0.0;
    pl_dissipation = 0.0;
    pl_stiffness = 0.0;
    pl_deepest = 0.0;
    volume_points();
    let rate = -(dot(hit.push, va - vb - cross(wb, xa - xb)) + dot(hit.turn_a, wa - wb));
    let depth = hit.volume / a_ref;
    let vn = -rate / a_ref;
    let law = normal_law(pair, depth, vn, pl_mass, r_star);
    let applied = applied_normal(pair, law);
    let per_volume = applied / a_ref;
    let normal_force = hit.push * per_volume + pl_force;
    out.torque_a = hit.turn_a * per_volume + pl_torque_a;
    out.torque_b = hit.turn_b * per_volume + pl_torque_b;
    out.elastic = law.z + pl_elastic;
    out.dissipation = pl_dissipation - (applied - law.x) * vn;
    let n = hit.normal;
    out.normal = max(dot(normal_force, n), 0.0);
    let v = relative_velocity(hit.point);
    let vt = v - n * dot(v, n);
    let gain = length(hit.push) / a_ref;
    let t = tangential_part(pair, out.normal, law.w * gain * gain + pl_stiffness, depth, r_star, m_star, n, vt, old_spring);
    out.force = normal_force + t.force;
    out.torque_a += cross(hit.point - xa, t.force);
    out.torque_b -= cross(hit.point - xb, t.force);
    out.elastic += t.spring.w;
    out.dissipation += t.slip_loss - dot(t.force, vt);
    out.spring = t.spring;
    return out;
}

// The patch radius of twisting friction on a volume contact of area `area`: (2/3)√(area/π).
fn area_spread(area: f32) -> f32 {
    return (2.0 / 3.0) * sqrt(area / 3.14159265);
}

// Two polyhedra a (lower id) and b, d = x_a − x_b, in the volume model.
fn volume_polyhedron_pair(a: u32, b: u32, d: vec3<f32>) -> PairOut {
    var out = PairOut(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, -1.0, vec4<f32>(0.0));
    let sa = shape_of(a);
    let sb = shape_of(b);
    let hit = volume_pair(sa, orient[a], sb, orient[b], d, shape_edge_density(sb));
    if !hit.hit {
        return out;
    }
    let ca = shape_contact(sa);
    let cb = shape_contact(sb);
    let weight = max(shape_face_on_weight(sa), shape_face_on_weight(sb));
    let spin_a = seen_spin(a);
    let spin_b = seen_spin(b);
    let m_star = 1.0 / (vel[a].w + vel[b].w);
    let ra = equivalent_radius(a);
    let rb = equivalent_radius(b);
    let r_star = ra * rb / (ra + rb);
    var old_spring = vec4<f32>(0.0);
    if HISTORY {
        old_spring = find_spring(props[a].z, props[b].z);
    }
    let pair = props[a].y * params.materials + props[b].y;
    let f = volume_force(pair, hit, min(ca.x, cb.x), weight, seen_velocity(a), spin_a, d, seen_velocity(b), spin_b, vec3<f32>(0.0), m_star, r_star, old_spring);
    out.force = f.force;
    out.spring = f.spring;
    out.torque_a = f.torque_a;
    out.torque_b = f.torque_b;
    let spin = spin_a - spin_b;
    let inv_n = inverse_inertia_about(a, hit.normal) + inverse_inertia_about(b, hit.normal);
    let twist = twisting_torque(area_spread(hit.area), tables[PAIR_ENTRY_WORDS * pair + 1u].y, f.normal, hit.normal, spin, inv_n);
    out.torque_a += twist;
    out.torque_b -= twist;
    out.dissipation = f.dissipation - dot(twist, spin);
    if ROLLING {
        // Rolling only: the spin about the normal is twisting friction's (two caps on one axis could reverse it).
        let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r_star, f.normal, spin - hit.normal * dot(spin, hit.normal), omega[a].w + omega[b].w);
        out.torque_a += roll;
        out.torque_b -= roll;
        out.dissipation -= dot(roll, spin);
    }
    out.elastic = f.elastic;
    out.ratio = hit.depth / min(ra, rb);
    return out;
}

// A polyhedral particle i against wall k (entry at `base`) in the volume model, into the sum;
// returns the power the wall delivers: F · v_wall(x_i) + Ω_wall · τ.
fn volume_wall_contact(s: ptr<function, Sum>, i: u32, k: u32, base: u32) -> f32 {
    let x = pos[i].xyz;
    let shape = shape_of(i);
    var hit = no_volume_hit();
    switch wall_kind(base) {
        case WALL_PRISM: {
            if PRISMS {
                let hull = prism_data(base) + PRISM_HULL;
                let centre = tables[hull];
                // The hull's edges weigh as the particle's, as on the CPU; loads relative to the walls' origin.
                hit = volume_pair(shape, orient[i], u32(centre.w), tables[hull + 1u], x - centre.xyz, shape_edge_density(shape));
                hit.point += centre.xyz;
                vc_out_shift += centre.xyz;
                hit.turn_b = vec3<f32>(0.0);
            }
        }
        default: {
            let entry = array<vec4<f32>, WALL_ENTRY_WORDS>(tables[base], tables[base + 1u], tables[base + 2u], tables[base + 3u], tables[base + 4u], tables[base + 5u]);
            hit = volume_wall(shape, orient[i], x, entry);
        }
    }
    if !hit.hit {
        return 0.0;
    }
    let w = seen_spin(i);
    var v_wall = vec3<f32>(0.0);
    var wall_w = vec3<f32>(0.0);
    if MOVING {
        v_wall = wall_velocity(base, x, hit.normal);
        wall_w = wall_spin(base);
    }
    let pair = props[i].y * params.materials + wall_material(base);
    let r = equivalent_radius(i);
    var old_spring = vec4<f32>(0.0);
    if HISTORY {
        old_spring = find_spring(props[i].z, WALL_KEY | k);
    }
    let f = volume_force(pair, hit, shape_contact(shape).x, shape_face_on_weight(shape), seen_velocity(i), w, x, v_wall, wall_w, x, alpha[i].w, r, old_spring);
    if hit.volume <= 0.0 && pl_deepest <= 0.0 {
        return 0.0;
    }
    if HISTORY {
        (*s).springs = keep_spring(props[i].z, (*s).springs, WALL_KEY | k, f.spring);
    }
    // Twisting friction and rolling resistance act against the spin relative to the wall.
    let spin = w - wall_w;
    let twist = twisting_torque(area_spread(hit.area), tables[PAIR_ENTRY_WORDS * pair + 1u].y, f.normal, hit.normal, spin, inverse_inertia_about(i, hit.normal));
    (*s).force += f.force;
    (*s).torque += f.torque_a + twist;
    (*s).elastic += f.elastic;
    (*s).dissipation += f.dissipation - dot(twist, spin);
    var power = dot(f.force, v_wall) + dot(f.torque_a + twist, wall_w);
    if ROLLING {
        let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r, f.normal, spin - hit.normal * dot(spin, hit.normal), omega[i].w);
        (*s).torque += roll;
        (*s).dissipation -= dot(roll, spin);
        power += dot(roll, wall_w);
    }
    (*s).contacts += 1u;
    (*s).ratio = max((*s).ratio, max(hit.depth, pl_deepest) / r);
    return power;
}
