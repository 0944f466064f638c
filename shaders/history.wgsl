// Contact history on the device (CPU: tumble_contact::history_force and
// tumble_cpu::history): tangential springs per contact and rolling resistance.
//
// Slots are indexed by the particle's ORIGINAL id (props.z), never by its
// array slot, so the periodic re-sort by cell never moves them. One generation
// holds, per id, `params.history_slots` slots of vec4<u32> (spring xyz as f32 bits,
// key: the neighbour's id, or WALL_KEY | wall), then after all n * slots entries
// one count entry per id (HISTORY_COUNT_ENTRIES): (slots in use, springs needed this step,
// most ever needed, unused), then per id ceil(slots / HISTORY_ENERGIES_PER_ENTRY) entries of
// stored energies (½ k_t |ξ|² as f32 bits, slot k in word k % 4 of entry k / 4). The counts let
// the host report an overflow without atomics; the energies are what a spring
// takes with it when its contact ends (k_t depends on the overlap then, so ξ
// alone cannot give it back).
// Two generations: the pass reads `hist_old` and writes `hist_new`; the host
// swaps the two bind groups after every committed pass (not the t = 0 one).
// Each invocation writes only its own particle's slots, count and energy entries.

// Index of id `owner`'s count entry.
fn history_count_index(owner: u32) -> u32 {
    return params.particles * params.history_slots + owner * HISTORY_COUNT_ENTRIES;
}

// Index of the entry holding the stored energy of `owner`'s slot `k` (in word k % 4).
fn history_energy_index(owner: u32, k: u32) -> u32 {
    let slots = params.history_slots;
    let rows = (slots + HISTORY_ENERGIES_PER_ENTRY - 1u) / HISTORY_ENERGIES_PER_ENTRY;
    return params.particles * (slots + HISTORY_COUNT_ENTRIES) + owner * rows + k / HISTORY_ENERGIES_PER_ENTRY;
}

// The spring particle `owner` held for `key` last step (ξ, stored energy), zero when the contact is new.
fn find_spring(owner: u32, key: u32) -> vec4<f32> {
    let slots = params.history_slots;
    let base = owner * slots;
    let used = min(hist_old[history_count_index(owner)].x, slots);
    for (var k = 0u; k < used; k++) {
        let e = hist_old[base + k];
        if e.w == key {
            let energy = bitcast<f32>(hist_old[history_energy_index(owner, k)][k % HISTORY_ENERGIES_PER_ENTRY]);
            return vec4<f32>(bitcast<vec3<f32>>(e.xyz), energy);
        }
    }
    return vec4<f32>(0.0);
}

// Stores one spring (ξ, stored energy) of `owner` in slot `used` if there is room and
// returns the springs counted (a zero spring is neither stored nor counted).
fn keep_spring(owner: u32, used: u32, key: u32, spring: vec4<f32>) -> u32 {
    if all(spring.xyz == vec3<f32>(0.0)) {
        return used;
    }
    let slots = params.history_slots;
    if used < slots {
        hist_new[owner * slots + used] = vec4<u32>(bitcast<vec3<u32>>(spring.xyz), key);
        // The whole entry is rewritten (all four words are this particle's): plain vec4 stores on every backend.
        let e = history_energy_index(owner, used);
        var energies = hist_new[e];
        energies[used % HISTORY_ENERGIES_PER_ENTRY] = bitcast<u32>(spring.w);
        hist_new[e] = energies;
    }
    return used + 1u;
}

// The energy `owner`'s springs of last step take with them because their contact ended
// (not kept among the `used` written this pass): booked once per pair as on the CPU
// (tumble_cpu's book_ended_springs), on the lower id's side, walls on the particle's.
fn ended_spring_energy(owner: u32, used: u32) -> f32 {
    let slots = params.history_slots;
    let base = owner * slots;
    let old_used = min(hist_old[history_count_index(owner)].x, slots);
    let kept = min(used, slots);
    var ended = 0.0;
    for (var k = 0u; k < old_used; k++) {
        let key = hist_old[base + k].w;
        if (key & WALL_KEY) == 0u && key < owner {
            continue;
        }
        var found = false;
        for (var m = 0u; m < kept; m++) {
            if hist_new[base + m].w == key {
                found = true;
                break;
            }
        }
        if !found {
            ended += bitcast<f32>(hist_old[history_energy_index(owner, k)][k % HISTORY_ENERGIES_PER_ENTRY]);
        }
    }
    return ended;
}

// Closes `owner`'s slots for this pass.
fn close_springs(owner: u32, used: u32) {
    let c = history_count_index(owner);
    let most = max(hist_old[c].z, used);
    hist_new[c] = vec4<u32>(min(used, params.history_slots), used, most, 0u);
}

struct Spring {
    force: vec3<f32>,
    spring: vec3<f32>,
    energy: f32,
    dissipation: f32,
}

// One step of a history contact (pair table t1 = (TANGENTIAL_HISTORY_LINEAR or _MINDLIN, μ,
// k_t or G*, damping ratio or β), t2.w = linear damping η [N s/m]): the old
// spring rotated into the tangent plane keeping its length, ξ += v_t Δt, then the
// sliding rule of tumble_contact::history_force with L = μ·normal (normal = max(F_n, 0)):
// a spring past L slides at L along −ξ̂ with ξ truncated to −F_t/k_t and no dashpot; otherwise F_t = −k_t ξ − η_t v_t, scaled
// back to L if the dashpot takes it past, ξ kept.
// `old_spring` = (old ξ, its stored energy); the dissipation is the work done on the
// contact minus the change of stored energy, as on the CPU (so a Mindlin k_t that
// changed with the overlap is booked too).
fn history_force(t1: vec4<f32>, t2: vec4<f32>, normal: f32, overlap: f32, r_star: f32, m_star: f32, old_spring: vec4<f32>, n: vec3<f32>, vt: vec3<f32>) -> Spring {
    var k_t = t1.z;
    var eta_t = t2.w;
    if u32(t1.x) == TANGENTIAL_HISTORY_LINEAR {
        if t1.w > 0.0 {
            eta_t = t2.w + 2.0 * t1.w * sqrt(m_star * k_t);
        }
    } else {
        k_t = 8.0 * t1.z * sqrt(r_star * overlap);
        eta_t = -2.0 * sqrt(5.0 / 6.0) * t1.w * sqrt(k_t * m_star);
    }
    let dt = params.dt;
    let old = old_spring.xyz;
    let old_len2 = dot(old, old);
    var xi = old - n * dot(n, old);
    if old_len2 > 0.0 {
        let len2 = dot(xi, xi);
        if len2 > 0.0 {
            xi *= sqrt(old_len2 / len2);
        }
    }
    xi += vt * dt;
    let limit = t1.y * max(normal, 0.0);
    let elastic = -k_t * xi;
    let elastic_magnitude = length(elastic);
    var force: vec3<f32>;
    if elastic_magnitude > limit {
        force = elastic * (limit / elastic_magnitude);
        if k_t > 0.0 {
            xi = -force / k_t;
        } else {
            xi = vec3<f32>(0.0);
        }
    } else {
        force = elastic - eta_t * vt;
        let magnitude = length(force);
        if magnitude > limit {
            force *= limit / magnitude;
        }
    }
    let energy = 0.5 * k_t * dot(xi, xi);
    var dissipation = 0.0;
    if dt > 0.0 {
        dissipation = -dot(force, vt) - (energy - old_spring.w) / dt;
    }
    return Spring(force, xi, energy, dissipation);
}

// Rolling resistance on i: −μ_r R* |F_n| ω̂_rel, capped so that alone it would
// not reverse ω_rel within the step (`inv_inertia_sum` = 1/I_i + 1/I_j).
fn rolling_torque(mu_r: f32, r_star: f32, normal: f32, w_rel: vec3<f32>, inv_inertia_sum: f32) -> vec3<f32> {
    let w = length(w_rel);
    if w == 0.0 || mu_r == 0.0 {
        return vec3<f32>(0.0);
    }
    var torque = mu_r * r_star * normal;
    let dt = params.dt;
    if inv_inertia_sum > 0.0 && dt > 0.0 {
        torque = min(torque, w / (inv_inertia_sum * dt));
    }
    return w_rel * (-torque / w);
}
