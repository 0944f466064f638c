// The fluid's step (bindings: bindings.rs, SPH_STEP), per evaluation:
//
// fluid_wall_state   each fluid particle's pressure from the Tait equation; each wall
//                    particle's pressure, density and viscous velocity extrapolated from the
//                    fluid around it (Adami, Hu & Adams 2012)
// fluid_rates        each fluid particle's acceleration, density rate and XSPH correction, and
//                    each floating body's particle the fluid's force on it
// fluid_body_sums    per floating body, that force summed and its moment about the centre
//
// and the symplectic scheme's halves (fluid_first_half, fluid_second_half). Every sum is
// gathered by its particle over the cells around it in slot order: no atomics, the same
// result run to run. The equations are tumble-sph's (rates.rs, pass.rs), term for term.

// The affine map of the motion table's three rows from `row`, at x.
fn motion_map(row: u32, x: vec3<f32>) -> vec3<f32> {
    let r0 = motions[row];
    let r1 = motions[row + 1u];
    let r2 = motions[row + 2u];
    return vec3<f32>(dot(r0.xyz, x) + r0.w, dot(r1.xyz, x) + r1.w, dot(r2.xyz, x) + r2.w);
}

// The first row of wall number `wall`'s motion table (wall > 0: a wall moving by a motion).
fn motion_row(wall: u32) -> u32 {
    return (wall - 1u) * SPH_MOTION_WORDS;
}

// Where a wall particle at x moves over the half step, and its velocity there: a moving wall's
// by its motion table, any other's with its own velocity.
fn wall_move(a: u32, x: vec3<f32>, v: vec3<f32>) -> array<vec3<f32>, 2> {
    let wall = tags[a].z;
    if wall == 0u {
        return array<vec3<f32>, 2>(x + fluid.step.y * v, v);
    }
    let to = motion_map(motion_row(wall), x);
    return array<vec3<f32>, 2>(to, motion_map(motion_row(wall) + 3u, to));
}

// The cells around a particle, each once: 27 in 3D, 9 in 2D, fewer at closed sides and on
// short periodic axes.
struct NeighbourCells {
    count: u32,
    cells: array<u32, 27>,
}

// The cells around sorted slot `a` (its cell from the sort, tags.w).
fn neighbour_cells(a: u32) -> NeighbourCells {
    let c = tags[a].w;
    let home = vec3<i32>(i32(c % fluid.dims.x), i32((c / fluid.dims.x) % fluid.dims.y), i32(c / (fluid.dims.x * fluid.dims.y)));
    let sx = cell_span(home.x, 0u);
    let sy = cell_span(home.y, 1u);
    let sz = cell_span(home.z, 2u);
    var around: NeighbourCells;
    around.count = 0u;
    for (var oz = 0; oz < sz.y; oz++) {
        for (var oy = 0; oy < sy.y; oy++) {
            for (var ox = 0; ox < sx.y; ox++) {
                around.cells[around.count] = cell_number(vec3<i32>(wrap_cell(sx.x + ox, 0u), wrap_cell(sy.x + oy, 1u), wrap_cell(sz.x + oz, 2u)));
                around.count++;
            }
        }
    }
    return around;
}

@compute @workgroup_size(WORKGROUP)
fn fluid_wall_state(@builtin(global_invocation_id) gid: vec3<u32>) {
    let a = fluid_index(gid);
    if a >= fluid.counts.x {
        return;
    }
    let xa = pos[a];
    let va = vel[a];
    var p = 0.0;
    var rho = va.w;
    var viscous_velocity = va.xyz;
    var fluid_flag = 1.0;
    if tags[a].x == SPH_FLUID {
        p = tait_pressure(rho);
    } else {
        fluid_flag = 0.0;
        var sum_w = 0.0;
        var sum_p = 0.0;
        var sum_rho_r = vec3<f32>(0.0);
        var sum_v = vec3<f32>(0.0);
        let around = neighbour_cells(a);
        for (var k = 0u; k < around.count; k++) {
            let n = around.cells[k];
            for (var b = cell_start[n]; b < cell_start[n + 1u]; b++) {
                if tags[b].x != SPH_FLUID {
                    continue;
                }
                let d = fluid_separation(xa.xyz, pos[b].xyz);
                let r2 = dot(d, d);
                if r2 >= fluid.kernel.x {
                    continue;
                }
                let w = wendland(sqrt(r2)).x;
                let vb = vel[b];
                sum_w += w;
                sum_p += tait_pressure(vb.w) * w;
                sum_rho_r += (vb.w * w) * d;
                sum_v += w * vb.xyz;
            }
        }
        if sum_w > 0.0 {
            // A moving wall's own acceleration enters as a body force of the opposite sign.
            var apparent = fluid.body_acceleration.xyz;
            if tags[a].z > 0u {
                apparent -= motion_map(motion_row(tags[a].z) + 6u, xa.xyz);
            }
            p = max((sum_p + dot(apparent, sum_rho_r)) / sum_w, 0.0);
            rho = tait_density(p);
            viscous_velocity = 2.0 * va.xyz - sum_v / sum_w;
        } else {
            p = 0.0;
            rho = fluid.eos.x;
        }
        // Only wall particles write their density, and this pass reads only the fluid's.
        vel[a].w = rho;
    }
    var tensile = 0.0;
    if method_has(SPH_TENSILE) && p < 0.0 {
        tensile = -0.2 * p / (rho * rho);
    }
    state[a] = vec4<f32>(p, p / (rho * rho), xa.w / rho, tensile);
    viscous[a] = vec4<f32>(viscous_velocity, fluid_flag);
}

@compute @workgroup_size(WORKGROUP)
fn fluid_rates(@builtin(global_invocation_id) gid: vec3<u32>) {
    let a = fluid_index(gid);
    if a >= fluid.counts.x {
        return;
    }
    if tags[a].x != SPH_FLUID {
        // A floating body's particle keeps the fluid's force on it where a fluid particle keeps
        // its rates; fluid_body_sums adds them up.
        var reaction = vec3<f32>(0.0);
        let wall = tags[a].z;
        if wall >= fluid.bodies.x && wall < fluid.bodies.x + fluid.bodies.y {
            reaction = body_reaction(a);
        }
        rate[a] = vec4<f32>(reaction, 0.0);
        xsph[a] = vec4<f32>(0.0);
        return;
    }
    let laminar = method_has(SPH_LAMINAR);
    let diffuse = method_has(SPH_DIFFUSE);
    let tensile = method_has(SPH_TENSILE);
    let with_xsph = method_has(SPH_XSPH);
    let xa = pos[a].xyz;
    let va4 = vel[a];
    let va = va4.xyz;
    let rho_a = va4.w;
    let sa = state[a];
    var acc = vec3<f32>(0.0);
    var continuity = 0.0;
    var diffusion = 0.0;
    var correction = vec3<f32>(0.0);
    let around = neighbour_cells(a);
    for (var k = 0u; k < around.count; k++) {
        let n = around.cells[k];
        for (var b = cell_start[n]; b < cell_start[n + 1u]; b++) {
            let d = fluid_separation(xa, pos[b].xyz);
            let r2 = dot(d, d);
            if r2 >= fluid.kernel.x || b == a {
                continue;
            }
            let r = sqrt(r2);
            let kernel = wendland(r);
            let w = kernel.x;
            let gw = kernel.y;
            let vb = vel[b];
            let viscous_b = viscous[b];
            let sb = state[b];
            let rho_b = vb.w;
            let fluid_b = viscous_b.w;
            let m_b = pos[b].w;
            // Continuity sees the neighbour's own velocity, the viscous terms Adami's.
            continuity += m_b * dot(va - vb.xyz, d) * gw;
            var p_term = sa.y + sb.y;
            if tensile {
                let f = w * fluid.terms.x;
                let f2 = f * f;
                p_term += (sa.w + sb.w) * f2 * f2;
            }
            let mean_rho = 0.5 * (rho_a + rho_b);
            if laminar {
                let nu = m_b * fluid.terms.w * r2 * gw / (rho_a * rho_b * (r2 + fluid.terms.z));
                acc += nu * (va - viscous_b.xyz);
            } else {
                let vr = dot(va - viscous_b.xyz, d);
                p_term -= fluid.more_terms.x * min(vr, 0.0) / (mean_rho * (r2 + fluid.terms.y));
            }
            // A linear penalty against wall particles only: zero at r₀ and beyond.
            let repulsion = (1.0 - fluid_b) * fluid.more_terms.z * max(fluid.more_terms.y - r, 0.0) / max(r, fluid.extent.w);
            acc += (repulsion - m_b * p_term * gw) * d;
            if diffuse {
                let drho_ab = rho_a - rho_b - dot(fluid.hydrostatic.xyz, d);
                diffusion += fluid_b * (2.0 * drho_ab * r2 * gw / (r2 + fluid.terms.y) * sb.z);
            }
            if with_xsph {
                correction -= (fluid_b * (m_b / mean_rho * w)) * (va - vb.xyz);
            }
        }
    }
    rate[a] = vec4<f32>(acc + fluid.body_acceleration.xyz, continuity + fluid.more_terms.w * diffusion);
    xsph[a] = vec4<f32>(fluid.hydrostatic.w * correction, 0.0);
}

// The force the fluid around wall particle `w` (a floating body's) exerts on it: minus what each
// fluid neighbour feels from it in fluid_rates, term for term (tumble-sph's wall_reaction).
fn body_reaction(w: u32) -> vec3<f32> {
    let laminar = method_has(SPH_LAMINAR);
    let tensile = method_has(SPH_TENSILE);
    let xw = pos[w];
    let vvw = viscous[w].xyz;
    let rho_w = vel[w].w;
    let sw = state[w];
    let m_w = xw.w;
    var force = vec3<f32>(0.0);
    let around = neighbour_cells(w);
    for (var k = 0u; k < around.count; k++) {
        let n = around.cells[k];
        for (var f = cell_start[n]; f < cell_start[n + 1u]; f++) {
            if tags[f].x != SPH_FLUID {
                continue;
            }
            let xf = pos[f];
            let d = fluid_separation(xf.xyz, xw.xyz);
            let r2 = dot(d, d);
            if r2 >= fluid.kernel.x {
                continue;
            }
            let r = sqrt(r2);
            let kernel = wendland(r);
            let gw = kernel.y;
            let vf = vel[f];
            let rho_f = vf.w;
            let sf = state[f];
            var p_term = sf.y + sw.y;
            if tensile {
                let x = kernel.x * fluid.terms.x;
                let x2 = x * x;
                p_term += (sf.w + sw.w) * x2 * x2;
            }
            var acceleration = vec3<f32>(0.0);
            if laminar {
                let nu = m_w * fluid.terms.w * r2 * gw / (rho_f * rho_w * (r2 + fluid.terms.z));
                acceleration = nu * (vf.xyz - vvw);
            } else {
                let vr = dot(vf.xyz - vvw, d);
                p_term -= fluid.more_terms.x * min(vr, 0.0) / (0.5 * (rho_f + rho_w) * (r2 + fluid.terms.y));
            }
            let repulsion = fluid.more_terms.z * max(fluid.more_terms.y - r, 0.0) / max(r, fluid.extent.w);
            acceleration += (repulsion - m_w * p_term * gw) * d;
            force -= xf.w * acceleration;
        }
    }
    return force;
}

var<workgroup> partial_force: array<vec3<f32>, WORKGROUP>;
var<workgroup> partial_moment: array<vec3<f32>, WORKGROUP>;

// One workgroup per floating body: the fluid's force on it and the moment about its centre,
// summed over its particles in slot order by strides, then pairwise in a fixed tree.
@compute @workgroup_size(WORKGROUP)
fn fluid_body_sums(@builtin(local_invocation_index) i: u32, @builtin(workgroup_id) group: vec3<u32>) {
    let body = group.x;
    let wall = fluid.bodies.x + body;
    let centre = motions[fluid.bodies.z + body].xyz;
    var force = vec3<f32>(0.0);
    var moment = vec3<f32>(0.0);
    for (var a = i; a < fluid.counts.x; a += WORKGROUP) {
        if tags[a].x != SPH_FLUID && tags[a].z == wall {
            let f = rate[a].xyz;
            force += f;
            moment += cross(fluid_separation(pos[a].xyz, centre), f);
        }
    }
    partial_force[i] = force;
    partial_moment[i] = moment;
    workgroupBarrier();
    for (var stride = WORKGROUP / 2u; stride > 0u; stride = stride / 2u) {
        if i < stride {
            partial_force[i] += partial_force[i + stride];
            partial_moment[i] += partial_moment[i + stride];
        }
        workgroupBarrier();
    }
    if i == 0u {
        body_sums[2u * body] = vec4<f32>(partial_force[0], 0.0);
        body_sums[2u * body + 1u] = vec4<f32>(partial_moment[0], 0.0);
    }
}

// The first half of the symplectic step: the fluid keeps v and ρ of the step's start, then
// drifts with v + XSPH while v and ρ advance half a step; wall particles move with their
// velocity, or by their wall's motion (which then gives their velocity).
@compute @workgroup_size(WORKGROUP)
fn fluid_first_half(@builtin(global_invocation_id) gid: vec3<u32>) {
    let a = fluid_index(gid);
    if a >= fluid.counts.x {
        return;
    }
    let half = fluid.step.y;
    let v = vel[a];
    let x = pos[a];
    if tags[a].x == SPH_FLUID {
        start[a] = v;
        let r = rate[a];
        vel[a] = vec4<f32>(v.xyz + half * r.xyz, v.w + half * r.w);
        pos[a] = vec4<f32>(fluid_wrap(x.xyz + half * (v.xyz + xsph[a].xyz)), x.w);
    } else {
        let moved = wall_move(a, x.xyz, v.xyz);
        vel[a] = vec4<f32>(moved[1], v.w);
        pos[a] = vec4<f32>(fluid_wrap(moved[0]), x.w);
    }
}

// The second half: v = v⁰ + Δt a, ρ = ρ⁰ (2 − ε)/(2 + ε) with ε = −Δt (dρ/dt)/ρ at the half
// step, and the drift with the new v + XSPH.
@compute @workgroup_size(WORKGROUP)
fn fluid_second_half(@builtin(global_invocation_id) gid: vec3<u32>) {
    let a = fluid_index(gid);
    if a >= fluid.counts.x {
        return;
    }
    let dt = fluid.step.x;
    let half = fluid.step.y;
    let v = vel[a];
    let x = pos[a];
    if tags[a].x == SPH_FLUID {
        let s = start[a];
        let r = rate[a];
        let velocity = s.xyz + dt * r.xyz;
        let eps = -dt * r.w / v.w;
        vel[a] = vec4<f32>(velocity, s.w * (2.0 - eps) / (2.0 + eps));
        pos[a] = vec4<f32>(fluid_wrap(x.xyz + half * (velocity + xsph[a].xyz)), x.w);
    } else {
        let moved = wall_move(a, x.xyz, v.xyz);
        vel[a] = vec4<f32>(moved[1], v.w);
        pos[a] = vec4<f32>(fluid_wrap(moved[0]), x.w);
    }
}
