// Unit quaternions (x, y, z, w), body to world, and the rigid-body rotation
// updates of tumble-integrate in f32 (free_rotation, rotate_orientation).
fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

fn quat_conj(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(-q.xyz, q.w);
}

// a ∘ b (apply b first).
fn quat_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

// One Newton step after inverseSqrt: GPU inverseSqrt may be a few ulp off in one
// direction, and a quaternion a little short of unit length scales what it rotates
// (the angular momentum, every step).
fn quat_normalize(q: vec4<f32>) -> vec4<f32> {
    let p = q * inverseSqrt(dot(q, q));
    return p * (1.5 - 0.5 * dot(p, p));
}

// The rotation matrix (columns: the body axes in the world).
fn quat_matrix(q_in: vec4<f32>) -> mat3x3<f32> {
    let q = quat_normalize(q_in);
    let x = q.x;
    let y = q.y;
    let z = q.z;
    let w = q.w;
    return mat3x3<f32>(
        vec3<f32>(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)),
        vec3<f32>(2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)),
        vec3<f32>(2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)),
    );
}

// The rotation about the unit axis e_k (k = 0, 1, 2) by the angle phi. Normalised:
// sin² + cos² of f32 (and of approximate GPU sin/cos) is not 1, and a turn that is not
// a unit quaternion would scale the angular momentum it rotates, step after step.
fn quat_about_axis(k: u32, phi: f32) -> vec4<f32> {
    var v = vec3<f32>(0.0);
    v[k] = sin(0.5 * phi);
    return quat_normalize(vec4<f32>(v, cos(0.5 * phi)));
}

// q advanced by the world angular velocity ω over Δt: normalise(Δq ∘ q).
fn rotate_orientation(q: vec4<f32>, w: vec3<f32>, dt: f32) -> vec4<f32> {
    let speed = length(w);
    if speed == 0.0 {
        return q;
    }
    let half = 0.5 * speed * dt;
    let dq = vec4<f32>(w / speed * sin(half), cos(half));
    return quat_normalize(quat_mul(dq, q));
}

struct FreeRotation {
    q: vec4<f32>,
    omega: vec3<f32>,
}

// Torque-free motion over Δt holding the world angular momentum L = I_w(q) ω
// (tumble_integrate::free_rotation): the symmetric splitting x(Δt/2) y(Δt/2) z(Δt)
// y(Δt/2) x(Δt/2) into exact turns about the body axes. Equal principal moments
// (to f32 rounding) turn about ω exactly.
fn free_rotation(q_in: vec4<f32>, inv_inertia: vec3<f32>, w: vec3<f32>, dt: f32) -> FreeRotation {
    let hi = max(inv_inertia.x, max(inv_inertia.y, inv_inertia.z));
    let lo = min(inv_inertia.x, min(inv_inertia.y, inv_inertia.z));
    if hi - lo <= 1e-6 * hi {
        return FreeRotation(rotate_orientation(q_in, w, dt), w);
    }
    var l = quat_rotate(quat_conj(q_in), w) / inv_inertia;
    var q = q_in;
    var axis = array<u32, 5>(0u, 1u, 2u, 1u, 0u);
    var share = array<f32, 5>(0.5, 0.5, 1.0, 0.5, 0.5);
    for (var s = 0u; s < 5u; s++) {
        let k = axis[s];
        let turn = quat_about_axis(k, l[k] * inv_inertia[k] * share[s] * dt);
        q = quat_mul(q, turn);
        l = quat_rotate(quat_conj(turn), l);
    }
    q = quat_normalize(q);
    return FreeRotation(q, quat_rotate(q, inv_inertia * l));
}

// R diag(k) Rᵀ v: a body-frame diagonal tensor applied to a world vector.
fn quat_tensor_times(q: vec4<f32>, k: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    return quat_rotate(q, k * quat_rotate(quat_conj(q), v));
}
