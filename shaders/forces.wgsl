// The contact pass, gather style: one invocation per particle visits the
// particles of its own and the neighbouring cells (and the walls) and sums only
// its own force and torque. Each pair is computed in canonical order (lower id
// first) from identical inputs on both sides and negated for the higher id, so
// pair forces are exactly equal and opposite. No float atomics, no shared
// writes: the result is the same on every run.
//
// Pair table entry k = a * materials + b (PAIR_ENTRY_WORDS vec4; codes as exact f32, read with u32()):
//   t0 = (normal: NORMAL_LINEAR or NORMAL_HERTZ; k_n or E*; damping ratio or β; √(π² + ln² e))
//   t1 = (tangential: TANGENTIAL_NONE, _VISCOUS_COULOMB, _STICK_LIMITED or _DYNAMIC_ONLY; μ;
//         c_t or k_f; 1 when k_f)
//        or (TANGENTIAL_HISTORY_LINEAR or _MINDLIN; μ; k_t or G*; damping ratio or β) (history.wgsl)
//   t2 = (k_c, 1 when attraction is clamped, rolling friction μ_r, linear history damping η)
// A law code not listed here gives no normal or tangential force. Walls follow the pair table (geometry.wgsl).
// Bindings: tumble-shaders' bindings.rs (FORCES).

// The velocity the forces see: Verlet's second-order estimate v_half + a_old Δt/2 of v_{n+1}.
fn seen_velocity(j: u32) -> vec3<f32> {
    if INTEGRATOR == INTEGRATOR_VERLET {
        return vel[j].xyz + acc[j].xyz * (0.5 * params.dt);
    }
    return vel[j].xyz;
}

fn seen_spin(j: u32) -> vec3<f32> {
    if INTEGRATOR == INTEGRATOR_VERLET {
        return omega[j].xyz + alpha[j].xyz * (0.5 * params.dt);
    }
    return omega[j].xyz;
}

struct ContactForce {
    force: vec3<f32>,
    tangential: vec3<f32>,
    elastic: f32,
    dissipation: f32,
    // max(F_n, 0) (friction capacity, rolling resistance) and the spring to keep: ξ, stored energy (history; zero when none).
    normal: f32,
    spring: vec4<f32>,
}

// The normal law of material pair `pair` at overlap δ ≥ 0 with normal velocity vn (positive
// separating): (elastic force, damping force, stored energy, tangent stiffness).
fn normal_law(pair: u32, overlap: f32, vn: f32, m_star: f32, r_star: f32) -> vec4<f32> {
    let t0 = tables[PAIR_ENTRY_WORDS * pair];
    let normal_law = u32(t0.x);
    var out = vec4<f32>(0.0);
    if LINEAR && normal_law == NORMAL_LINEAR {
        let stiffness = t0.y;
        out = vec4<f32>(stiffness * overlap, -2.0 * t0.z * sqrt(m_star * stiffness) * vn, 0.5 * stiffness * overlap * overlap, stiffness);
    }
    if HERTZ && normal_law == NORMAL_HERTZ {
        let root = sqrt(r_star * overlap);
        let k = 4.0 / 3.0 * t0.y * root;
        let stiffness = 2.0 * t0.y * root;
        out = vec4<f32>(k * overlap, 2.0 * sqrt(5.0 / 6.0) * t0.z * sqrt(stiffness * m_star) * vn, 0.4 * k * overlap * overlap, stiffness);
    }
    return out;
}

// The force the law applies: elastic plus damping, never pulling with no_attraction.
fn applied_normal(pair: u32, law: vec4<f32>) -> f32 {
    if tables[PAIR_ENTRY_WORDS * pair + 2u].y != 0.0 {
        return max(law.x + law.y, 0.0);
    }
    return law.x + law.y;
}

struct TangentialOut {
    force: vec3<f32>,
    // ξ and its stored energy (history; zero otherwise).
    spring: vec4<f32>,
    // Power lost to slip beyond the work −F_t · v_t (history: the spring's own book).
    slip_loss: f32,
}

// The tangential law of `pair` for a contact pressed by `normal` (max(F_n, 0)) with tangent
// slip vt; `stiffness` is the normal law's tangent stiffness (for laws timed by t_col).
fn tangential_part(pair: u32, normal: f32, stiffness: f32, overlap: f32, r_star: f32, m_star: f32, n: vec3<f32>, vt: vec3<f32>, old_spring: vec4<f32>) -> TangentialOut {
    var out = TangentialOut(vec3<f32>(0.0), vec4<f32>(0.0), 0.0);
    let t0 = tables[PAIR_ENTRY_WORDS * pair];
    let t1 = tables[PAIR_ENTRY_WORDS * pair + 1u];
    let t2 = tables[PAIR_ENTRY_WORDS * pair + 2u];
    let tangential_law = u32(t1.x);
    if HISTORY && (tangential_law == TANGENTIAL_HISTORY_LINEAR || tangential_law == TANGENTIAL_HISTORY_MINDLIN) {
        let h = history_force(t1, t2, normal, overlap, r_star, m_star, old_spring, n, vt);
        out.force = h.force;
        out.spring = vec4<f32>(h.spring, h.energy);
        out.slip_loss = h.dissipation + dot(h.force, vt);
    } else if TANGENTIAL && (tangential_law == TANGENTIAL_VISCOUS_COULOMB || tangential_law == TANGENTIAL_STICK_LIMITED || tangential_law == TANGENTIAL_DYNAMIC_ONLY) {
        let speed = length(vt);
        if speed > 0.0 {
            var magnitude = t1.y * normal;
            switch tangential_law {
                case TANGENTIAL_VISCOUS_COULOMB: {
                    var c_t = t1.z;
                    if t1.w != 0.0 {
                        // c_t = k_f t_col of this contact.
                        c_t = t1.z * sqrt(m_star / stiffness) * t0.w;
                    }
                    magnitude = min(magnitude, c_t * speed);
                }
                case TANGENTIAL_STICK_LIMITED: {
                    magnitude = min(magnitude, m_star * speed / params.dt);
                }
                default: {
                    // Dynamic-only: the Coulomb limit alone.
                }
            }
            out.force = vt * (-magnitude / speed);
        }
    }
    return out;
}

// `old_spring`: the contact's tangential spring from the last step and its stored energy (history only, else zero).
fn contact_force(pair: u32, n: vec3<f32>, overlap: f32, effect_overlap: f32, v_rel: vec3<f32>, m_star: f32, r_star: f32, old_spring: vec4<f32>) -> ContactForce {
    var out = ContactForce(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, 0.0, vec4<f32>(0.0));
    let t2 = tables[PAIR_ENTRY_WORDS * pair + 2u];
    if COHESION && t2.x > 0.0 && effect_overlap > 0.0 {
        out.force = n * (-t2.x * effect_overlap);
        out.elastic = -0.5 * t2.x * effect_overlap * effect_overlap;
    }
    if overlap >= 0.0 {
        let vn = dot(v_rel, n);
        let law = normal_law(pair, overlap, vn, m_star, r_star);
        let applied = applied_normal(pair, law);
        let vt = v_rel - n * vn;
        // The friction capacity: a pulling dashpot gives none.
        out.normal = max(applied, 0.0);
        let t = tangential_part(pair, out.normal, law.w, overlap, r_star, m_star, n, vt, old_spring);
        out.spring = t.spring;
        out.force += n * applied + t.force;
        out.tangential = t.force;
        out.elastic += law.z + t.spring.w;
        out.dissipation = t.slip_loss - ((applied - law.x) * vn + dot(t.force, vt));
    }
    return out;
}

struct PairOut {
    // Force on a; b receives the negation.
    force: vec3<f32>,
    torque_a: vec3<f32>,
    torque_b: vec3<f32>,
    elastic: f32,
    dissipation: f32,
    // δ / min(r_a, r_b), or negative when the bodies do not touch.
    ratio: f32,
    // The pair's new spring as a holds it: ξ, stored energy (history).
    spring: vec4<f32>,
}

// The contact of slots a and b, a holding the lower id.
fn pair_contact(a: u32, b: u32) -> PairOut {
    var out = PairOut(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, -1.0, vec4<f32>(0.0));
    var d = pos[a].xyz - pos[b].xyz;
    if PERIODIC {
        d = minimum_image(d);
    }
    let cutoff = bitcast<f32>(props[a].x) + bitcast<f32>(props[b].x);
    let d2 = dot(d, d);
    if d2 > cutoff * cutoff {
        return out;
    }
    if POLYHEDRA && (shape_of(a) != SPHERE_SHAPE || shape_of(b) != SPHERE_SHAPE) {
        return polyhedron_pair(a, b, d);
    }
    let distance = sqrt(d2);
    if distance <= 0.0 {
        return out;
    }
    let ra = pos[a].w;
    let rb = pos[b].w;
    let n = d / distance;
    let overlap = ra + rb - distance;
    var effect_overlap = 0.0;
    if COHESION {
        effect_overlap = cutoff - distance;
    }
    if overlap < 0.0 && (!COHESION || effect_overlap <= 0.0) {
        return out;
    }
    let arm_a = -n * (ra - 0.5 * overlap);
    let arm_b = arm_a + d;
    var v_rel = seen_velocity(a) - seen_velocity(b);
    if ROTATION {
        v_rel += cross(seen_spin(a), arm_a) - cross(seen_spin(b), arm_b);
    }
    let m_star = 1.0 / (vel[a].w + vel[b].w);
    let r_star = ra * rb / (ra + rb);
    var old_spring = vec4<f32>(0.0);
    if HISTORY {
        // Both sides read a's copy.
        old_spring = find_spring(props[a].z, props[b].z);
    }
    let pair = props[a].y * params.materials + props[b].y;
    let f = contact_force(pair, n, overlap, effect_overlap, v_rel, m_star, r_star, old_spring);
    out.force = f.force;
    out.spring = f.spring;
    if ROTATION {
        out.torque_a = cross(arm_a, f.tangential);
        out.torque_b = cross(arm_b, -f.tangential);
        if ROLLING {
            let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r_star, f.normal, seen_spin(a) - seen_spin(b), omega[a].w + omega[b].w);
            out.torque_a += roll;
            out.torque_b -= roll;
            // The couple opposes the relative rolling: all its work is dissipated.
            out.dissipation -= dot(roll, seen_spin(a) - seen_spin(b));
        }
    }
    out.elastic = f.elastic;
    out.dissipation = f.dissipation;
    if overlap >= 0.0 {
        out.ratio = overlap / min(ra, rb);
    }
    return out;
}

// Neighbour cell offsets along one axis: periodic axes with fewer than three
// cells visit each distinct cell once.
fn offset_range(periodic: bool, cells: u32) -> vec2<i32> {
    if periodic && cells == 1u {
        return vec2<i32>(0, 0);
    }
    if periodic && cells == 2u {
        return vec2<i32>(0, 1);
    }
    return vec2<i32>(-1, 1);
}

// The neighbour cell coordinate, or -1 outside a non-periodic axis.
fn neighbour_coordinate(c: i32, offset: i32, periodic: bool, cells: u32) -> i32 {
    let m = c + offset;
    if periodic {
        return (m + i32(cells)) % i32(cells);
    }
    if m < 0 || m >= i32(cells) {
        return -1;
    }
    return m;
}

// The neighbours in range one round of a particle's pairs takes (see `forces`).
const CANDIDATES: u32 = 32u;

struct Sum {
    force: vec3<f32>,
    torque: vec3<f32>,
    elastic: f32,
    dissipation: f32,
    contacts: u32,
    ratio: f32,
    // Springs kept (history; may exceed the slots: then the host stops the run).
    springs: u32,
}

fn add_pair(s: ptr<function, Sum>, i: u32, j: u32) {
    // One call site: on SIMD hardware both orders then run the same instructions.
    let mine = props[i].z < props[j].z;
    var a = j;
    var b = i;
    if mine {
        a = i;
        b = j;
    }
    let p = pair_contact(a, b);
    if HISTORY {
        // a keeps +ξ keyed by b, b keeps −ξ keyed by a; both keep the same stored energy.
        var spring = vec4<f32>(-p.spring.xyz, p.spring.w);
        if mine {
            spring = p.spring;
        }
        (*s).springs = keep_spring(props[i].z, (*s).springs, props[j].z, spring);
    }
    (*s).ratio = max((*s).ratio, p.ratio);
    if mine {
        (*s).force += p.force;
        (*s).torque += p.torque_a;
        // Energies and contacts are booked on the canonical side only.
        (*s).elastic += p.elastic;
        (*s).dissipation += p.dissipation;
        if p.ratio > 0.0 {
            (*s).contacts += 1u;
        }
    } else {
        (*s).force -= p.force;
        (*s).torque += p.torque_b;
    }
}

fn add_walls(s: ptr<function, Sum>, i: u32) {
    let xi = pos[i].xyz;
    let r = pos[i].w;
    let extra = bitcast<f32>(props[i].x) - r;
    let v = seen_velocity(i);
    let w = seen_spin(i);
    let mass = alpha[i].w;
    let walls_base = PAIR_ENTRY_WORDS * params.materials * params.materials;
    // Wall loads: walls come grouped in group order; each group's sum is booked once. The sum
    // holds one group's force and torque at a time, so each is booked without cancellation.
    let polyhedron = POLYHEDRA && shape_of(i) != SPHERE_SHAPE;
    let pair_force = (*s).force;
    let pair_torque = (*s).torque;
    var walls_force = vec3<f32>(0.0);
    var walls_torque = vec3<f32>(0.0);
    (*s).force = vec3<f32>(0.0);
    (*s).torque = vec3<f32>(0.0);
    var group = 0u;
    var power = 0.0;
    for (var k = 0u; k < params.walls; k++) {
        let base = walls_base + WALL_ENTRY_WORDS * k;
        let g = wall_group(base);
        if g != group {
            book_wall_load(i, group, power, (*s).force, (*s).torque);
            walls_force += (*s).force;
            walls_torque += (*s).torque;
            (*s).force = vec3<f32>(0.0);
            (*s).torque = vec3<f32>(0.0);
            group = g;
            power = 0.0;
        }
        if polyhedron {
            power += polyhedron_wall_contact(s, i, k, base);
            continue;
        }
        let p = wall_proximity(base, xi, r, extra);
        if !p.hit {
            continue;
        }
        let effect_overlap = p.overlap + extra;
        if p.overlap <= 0.0 && (!COHESION || effect_overlap <= 0.0) {
            continue;
        }
        let arm = p.point - xi;
        var v_rel = v;
        var v_wall = vec3<f32>(0.0);
        if MOVING {
            // A moving wall's velocity at the contact point enters the relative velocity.
            v_wall = wall_velocity(base, p.point, p.normal);
            v_rel -= v_wall;
        }
        if ROTATION {
            v_rel += cross(w, arm);
        }
        let pair = props[i].y * params.materials + wall_material(base);
        var old_spring = vec4<f32>(0.0);
        if HISTORY {
            old_spring = find_spring(props[i].z, WALL_KEY | k);
        }
        let f = contact_force(pair, p.normal, p.overlap, effect_overlap, v_rel, mass, r, old_spring);
        if HISTORY {
            (*s).springs = keep_spring(props[i].z, (*s).springs, WALL_KEY | k, f.spring);
        }
        (*s).force += f.force;
        if MOVING {
            power += dot(f.force, v_wall);
        }
        if ROTATION {
            (*s).torque += cross(arm, f.tangential);
            if ROLLING {
                // Rolling relative to the wall; the couple on the particle does work Ω_wall · τ.
                var spin = vec3<f32>(0.0);
                if MOVING {
                    spin = wall_spin(base);
                }
                let roll = rolling_torque(tables[PAIR_ENTRY_WORDS * pair + 2u].z, r, f.normal, w - spin, omega[i].w);
                (*s).torque += roll;
                (*s).dissipation -= dot(roll, w - spin);
                if MOVING {
                    power += dot(roll, spin);
                }
            }
        }
        (*s).elastic += f.elastic;
        (*s).dissipation += f.dissipation;
        if p.overlap > 0.0 {
            (*s).contacts += 1u;
            (*s).ratio = max((*s).ratio, p.overlap / r);
        }
    }
    if params.walls > 0u {
        book_wall_load(i, group, power, (*s).force, (*s).torque);
    }
    (*s).force = pair_force + (walls_force + (*s).force);
    (*s).torque = pair_torque + (walls_torque + (*s).torque);
}

@compute @workgroup_size(WORKGROUP)
fn forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if i >= params.particles {
        return;
    }
    var s = Sum(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, 0u, 0.0, 0u);
    let flags = props[i].w;
    if WALLS && (flags & (FLAG_DEAD | FLAG_FIXED)) != 0u {
        // No wall contacts: no wall load.
        for (var g = 0u; g < wall_groups(); g++) {
            let k = 2u * (props[i].z * wall_groups() + g);
            wall_load[k] = vec4<f32>(0.0);
            wall_load[k + 1u] = vec4<f32>(0.0);
        }
    }
    if (flags & FLAG_DEAD) == 0u {
        let fixed_i = (flags & FLAG_FIXED) != 0u;
        let xi = pos[i].xyz;
        let reach_i = bitcast<f32>(props[i].x);
        let c = cell[i];
        let dims = params.dims;
        let home = vec3<i32>(i32(c % dims.x), i32((c / dims.x) % dims.y), i32(c / (dims.x * dims.y)));
        let periodic = vec3<bool>(params.periodic.x != 0u, params.periodic.y != 0u, params.periodic.z != 0u);
        let rx = offset_range(periodic.x, dims.x);
        let ry = offset_range(periodic.y, dims.y);
        let rz = offset_range(periodic.z, dims.z);
        let nx = u32(rx.y - rx.x + 1);
        let ny = u32(ry.y - ry.x + 1);
        let cells = nx * ny * u32(rz.y - rz.x + 1);
        // The neighbours in range are collected first and their pairs computed after: lanes
        // that run together (a GPU's SIMD group, a CPU adapter's vector) then run a pair's long
        // body once per neighbour in range, not once for every candidate of the cells any of
        // them scans (6 times as many for spheres). The pairs keep the cells' slot order, so
        // the sums are the same bits.
        var q = 0u;
        var k = 0u;
        var end = 0u;
        loop {
            var found: array<u32, CANDIDATES>;
            var count = 0u;
            loop {
                if k == end {
                    if q == cells {
                        break;
                    }
                    // The next cell, x fastest, then y, then z.
                    let cx = neighbour_coordinate(home.x, rx.x + i32(q % nx), periodic.x, dims.x);
                    let cy = neighbour_coordinate(home.y, ry.x + i32((q / nx) % ny), periodic.y, dims.y);
                    let cz = neighbour_coordinate(home.z, rz.x + i32(q / (nx * ny)), periodic.z, dims.z);
                    q++;
                    if cx < 0 || cy < 0 || cz < 0 {
                        continue;
                    }
                    let nc = u32(cx) + dims.x * (u32(cy) + dims.y * u32(cz));
                    k = cell_start[nc];
                    end = cell_start[nc + 1u];
                    continue;
                }
                let j = cell_list[k];
                k++;
                if j == i || (fixed_i && (props[j].w & FLAG_FIXED) != 0u) {
                    continue;
                }
                // Cheap range test first; the pair itself is computed in canonical order.
                var d = xi - pos[j].xyz;
                if PERIODIC {
                    d = minimum_image(d);
                }
                let cutoff = reach_i + bitcast<f32>(props[j].x);
                if dot(d, d) > cutoff * cutoff {
                    continue;
                }
                found[count] = j;
                count++;
                if count == CANDIDATES {
                    break;
                }
            }
            for (var m = 0u; m < count; m++) {
                add_pair(&s, i, found[m]);
            }
            if count < CANDIDATES {
                break;
            }
        }
        if WALLS && !fixed_i {
            add_walls(&s, i);
        }
        if HISTORY && params.dt > 0.0 {
            // Springs whose contact ended take their stored energy with them: dissipated now.
            s.dissipation += ended_spring_energy(props[i].z, s.springs) / params.dt;
        }
    }
    force_out[i] = vec4<f32>(s.force, s.elastic);
    torque_out[i] = vec4<f32>(s.torque, s.dissipation);
    stats_out[i] = vec2<u32>(s.contacts, bitcast<u32>(s.ratio));
    if HISTORY {
        close_springs(props[i].z, s.springs);
    }
}
