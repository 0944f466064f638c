// Body forces and the update rules of the five integrators (docs/physics.md,
// "Integrators"), one invocation per particle:
//
// kick_drift  Verlet's first half: half kick with the stored acceleration, drift
// finish      accelerations from the contact sums plus gravity and drag, then
//             the plan's update (Verlet: the second half kick)
// initial     accelerations only, at t = 0 (no dissipation or fluid work booked)
//
// Then periodic axes are wrapped and particles that left through another side
// are flagged as removed (they sort into the removed bucket from then on).

// Bindings: tumble-shaders' bindings.rs (INTEGRATE).

fn shape_of(j: u32) -> u32 {
    return props[j].w >> SHAPE_SHIFT;
}

fn shape_word(i: u32) -> vec4<f32> {
    return tables[params.shape_base + i];
}

// Principal inverse inertia (body frame) of particle i: zero for fixed bodies.
fn inverse_inertia_body(i: u32) -> vec3<f32> {
    let s = shape_of(i);
    if s == SPHERE_SHAPE {
        return vec3<f32>(omega[i].w);
    }
    return shape_inertia(s).xyz * vel[i].w;
}

// Turns body i by its spin over Δt, torque-free (polyhedra scenes: every movable body,
// spheres included, carries an orientation), holding its world angular momentum.
fn drift_orientation(i: u32) {
    if !POLYHEDRA {
        return;
    }
    let k = inverse_inertia_body(i);
    if all(k == vec3<f32>(0.0)) {
        return;
    }
    let r = free_rotation(orient[i], k, omega[i].xyz, dt());
    orient[i] = r.q;
    omega[i] = vec4<f32>(r.omega, omega[i].w);
}

fn dt() -> f32 {
    return params.dt;
}

fn implicit() -> bool {
    return INTEGRATOR == INTEGRATOR_IMPLICIT_DRAG || INTEGRATOR == INTEGRATOR_IMPLICIT_DRAG_SYMPLECTIC;
}

// Kahan summation: (sum, compensation) plus x.
fn kahan(acc_in: vec2<f32>, x: f32) -> vec2<f32> {
    let y = x - acc_in.y;
    let t = acc_in.x + y;
    return vec2<f32>(t, (t - acc_in.x) - y);
}

// The fluid velocity at a position relative to the domain's centre.
fn flow_velocity(x_rel: vec3<f32>) -> vec3<f32> {
    if TAYLOR_GREEN {
        let x = x_rel + params.origin;
        let a = params.taylor_green_amplitude;
        let k = params.taylor_green_frequency;
        let h = 1.5707963267948966;
        let p = k * x + vec3<f32>(h);
        let s = sin(p);
        let c = cos(p);
        return vec3<f32>(a * c.x * s.y * s.z, a * s.x * c.y * s.z, -2.0 * a * s.x * s.y * c.z);
    }
    return params.flow;
}

// Explicit drag acceleration at (x, v) for drag parameter k.
fn drag_acceleration(x: vec3<f32>, v: vec3<f32>, k: f32) -> vec3<f32> {
    if DRAG == DRAG_STOKES {
        return (flow_velocity(x) - v) / k;
    }
    if DRAG == DRAG_QUADRATIC {
        return -v * (k * length(v));
    }
    return vec3<f32>(0.0);
}

// Wraps periodic axes, counting the box lengths taken off into the particle's image (by
// original id); flags the particle removed when it left through another side.
fn boundaries(i: u32) {
    var x = pos[i].xyz;
    var wraps = vec3<i32>(0);
    for (var k = 0; k < 3; k++) {
        let l = params.extent[k];
        let h = 0.5 * l;
        if params.periodic[k] != 0u {
            if x[k] >= h {
                x[k] -= l;
                wraps[k] += 1;
            } else if x[k] < -h {
                x[k] += l;
                wraps[k] -= 1;
            }
            if x[k] >= h || x[k] < -h {
                let from_min = x[k] + h;
                let lengths = floor(from_min / l);
                x[k] = from_min - lengths * l - h;
                wraps[k] += i32(lengths);
                if x[k] >= h {
                    x[k] = -h;
                    wraps[k] += 1;
                }
            }
        } else if x[k] < -h || x[k] > h {
            props[i].w |= FLAG_DEAD;
        }
    }
    if (props[i].w & FLAG_DEAD) == 0u {
        for (var k = 0u; k < params.outlets; k++) {
            if in_outlet(k, x) {
                props[i].w |= FLAG_DEAD | ((k + 1u) << OUTLET_SHIFT);
                break;
            }
        }
    }
    pos[i] = vec4<f32>(x, pos[i].w);
    if PERIODIC && any(wraps != vec3<i32>(0)) {
        let id = props[i].z;
        image[id] = vec4<i32>(image[id].xyz + wraps, 0);
    }
}

// Whether outlet k holds the point x (relative to the domain's centre, as the table is).
fn in_outlet(k: u32, x: vec3<f32>) -> bool {
    let base = params.outlet_base + k * OUTLET_ENTRIES;
    let a = tables[base + 1u].xyz;
    let b = tables[base + 2u].xyz;
    if u32(tables[base].x) == OUTLET_BOX {
        return all(x >= a) && all(x < b);
    }
    return dot(x - a, b) > 0.0;
}

fn alive(i: u32) -> bool {
    return i < params.particles && (props[i].w & FLAG_DEAD) == 0u;
}

// Accelerations from the contact sums, gravity and explicit drag at velocity v;
// books dissipation and fluid work when `book` is true.
fn accelerations(i: u32, v: vec3<f32>, explicit_drag: bool, book: bool) -> vec3<f32> {
    let inv_mass = vel[i].w;
    var a = vec3<f32>(0.0);
    var e = energy[i];
    if inv_mass != 0.0 {
        a = force_in[i].xyz * inv_mass + params.gravity;
        if DRAG != DRAG_NONE && explicit_drag {
            let ad = drag_acceleration(pos[i].xyz, v, acc[i].w);
            a += ad;
            if book {
                let w = kahan(vec2<f32>(e.y, e.w), dot(ad, v) / inv_mass * dt());
                e = vec4<f32>(e.x, w.x, e.z, w.y);
            }
        }
    }
    if ROTATION {
        var angular = torque_in[i].xyz * omega[i].w;
        if POLYHEDRA {
            // α = R I⁻¹ Rᵀ τ; the gyroscopic term lives in the torque-free drift.
            angular = quat_tensor_times(orient[i], inverse_inertia_body(i), torque_in[i].xyz);
        }
        alpha[i] = vec4<f32>(angular, alpha[i].w);
    }
    if book {
        let d = kahan(vec2<f32>(e.x, e.z), torque_in[i].w * dt());
        e = vec4<f32>(d.x, e.y, d.y, e.w);
        energy[i] = e;
    }
    acc[i] = vec4<f32>(a, acc[i].w);
    return a;
}

@compute @workgroup_size(WORKGROUP)
fn initial(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if !alive(i) {
        return;
    }
    accelerations(i, vel[i].xyz, !implicit(), false);
}

@compute @workgroup_size(WORKGROUP)
fn kick_drift(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if !alive(i) {
        return;
    }
    let h = 0.5 * dt();
    if vel[i].w != 0.0 {
        let v_half = vel[i].xyz + acc[i].xyz * h;
        vel[i] = vec4<f32>(v_half, vel[i].w);
        pos[i] = vec4<f32>(pos[i].xyz + v_half * dt(), pos[i].w);
    }
    if ROTATION {
        omega[i] = vec4<f32>(omega[i].xyz + alpha[i].xyz * h, omega[i].w);
    }
    drift_orientation(i);
    boundaries(i);
}

@compute @workgroup_size(WORKGROUP)
fn finish(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if !alive(i) {
        return;
    }
    let step = dt();
    let inv_mass = vel[i].w;
    if INTEGRATOR == INTEGRATOR_VERLET {
        // Velocity-dependent forces saw v_half + a_old Δt/2.
        let seen = vel[i].xyz + acc[i].xyz * (0.5 * step);
        let a = accelerations(i, seen, true, true);
        if inv_mass != 0.0 {
            vel[i] = vec4<f32>(vel[i].xyz + a * (0.5 * step), inv_mass);
        }
        if ROTATION {
            omega[i] = vec4<f32>(omega[i].xyz + alpha[i].xyz * (0.5 * step), omega[i].w);
        }
        return;
    }
    let a = accelerations(i, vel[i].xyz, !implicit(), true);
    if inv_mass != 0.0 {
        let x = pos[i].xyz;
        let v = vel[i].xyz;
        var x_new = x;
        var v_new = v;
        if INTEGRATOR == INTEGRATOR_EULER {
            x_new = x + v * step;
            v_new = v + a * step;
        } else if INTEGRATOR == INTEGRATOR_SYMPLECTIC_EULER {
            v_new = v + a * step;
            x_new = x + v_new * step;
        } else if implicit() {
            // Implicit drag with rate λ = 1/τ: v_new = (v + a Δt + λ u Δt) / (1 + λ Δt).
            var rate = 0.0;
            var u = vec3<f32>(0.0);
            if DRAG == DRAG_STOKES {
                rate = 1.0 / acc[i].w;
                u = flow_velocity(x);
            } else if DRAG == DRAG_QUADRATIC {
                // Quadratic drag linearised at the current speed: λ = α|v|/m.
                rate = acc[i].w * length(v);
            }
            v_new = (v + a * step + u * (rate * step)) / (1.0 + rate * step);
            if INTEGRATOR == INTEGRATOR_IMPLICIT_DRAG_SYMPLECTIC {
                x_new = x + v_new * step;
            } else {
                x_new = x + (v + v_new) * (0.5 * step);
            }
            if rate > 0.0 {
                // Work of the implicit drag m λ (u − v_new) over the step.
                let w = dot(u - v_new, v + v_new) * (0.5 * step * rate / inv_mass);
                let e = energy[i];
                let f = kahan(vec2<f32>(e.y, e.w), w);
                energy[i] = vec4<f32>(e.x, f.x, e.z, f.y);
            }
        }
        vel[i] = vec4<f32>(v_new, inv_mass);
        pos[i] = vec4<f32>(x_new, pos[i].w);
    }
    if ROTATION {
        omega[i] = vec4<f32>(omega[i].xyz + alpha[i].xyz * step, omega[i].w);
    }
    drift_orientation(i);
    boundaries(i);
}
