// Shared by the fluid's kernels (sph_sort.wgsl, sph_step.wgsl): the fluid's step parameters,
// the index helpers, its cell grid and the minimum image.
//
// Positions are relative to the fluid domain's centre (the best f32 precision). The cells are
// 2h plus a skin wide (tumble-sph's SKIN), so the grid of the sort at the start of a step still
// holds every pair within 2h at the half step. Particles beyond a closed side are binned into
// the edge cells.

// The fluid's step parameters (tumble-gpu's fluid::FluidParams, field for field).
struct FluidParams {
    // Particles, cells (the grid's; the scan has one spare bucket), the method's switches
    // (SPH_* bits), threads per dispatch row.
    counts: vec4<u32>,
    // Cells along x, y, z; w: the periodic axes as bits 0, 1, 2.
    dims: vec4<u32>,
    // The domain's lengths; w: the smallest distance the repulsion divides by.
    extent: vec4<f32>,
    // Cells per metre along each axis; w: unused.
    inv_cell: vec4<f32>,
    // (2h)², 1/h, −5α/h² (so that (dW/dr)/r = this · (1 − q/2)³), α of the kernel.
    kernel: vec4<f32>,
    // 1/W(Δp), η² of the artificial viscosity and diffusion, η² of the laminar term, 2μ.
    terms: vec4<f32>,
    // α c₀ h of the artificial viscosity, the wall repulsion's reach and stiffness, δ h c₀.
    more_terms: vec4<f32>,
    // ρ₀/c₀² times the external acceleration (Fourtakas's hydrostatic correction); w: XSPH's ε.
    hydrostatic: vec4<f32>,
    // Gravity plus the body force; w: unused.
    body_acceleration: vec4<f32>,
    // ρ₀, B of the Tait equation, 1/ρ₀, unused.
    eos: vec4<f32>,
    // Δt, Δt/2, unused, unused.
    step: vec4<f32>,
    // The first floating body's wall number, the bodies, the motion table's row of the first
    // body's centre, unused.
    bodies: vec4<u32>,
}

fn fluid_index(gid: vec3<u32>) -> u32 {
    return gid.x + gid.y * fluid.counts.w;
}

fn method_has(switch_bit: u32) -> bool {
    return (fluid.counts.z & switch_bit) != 0u;
}

fn periodic_axis(k: u32) -> bool {
    return ((fluid.dims.w >> k) & 1u) != 0u;
}

// The cell of a position (clamped into the grid along closed axes).
fn cell_coords(x: vec3<f32>) -> vec3<i32> {
    let u = floor((x + 0.5 * fluid.extent.xyz) * fluid.inv_cell.xyz);
    return clamp(vec3<i32>(u), vec3<i32>(0), vec3<i32>(fluid.dims.xyz) - vec3<i32>(1));
}

fn cell_number(c: vec3<i32>) -> u32 {
    return u32(c.x) + fluid.dims.x * (u32(c.y) + fluid.dims.y * u32(c.z));
}

// The separation a − b, the nearest image along periodic axes.
fn fluid_separation(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    var d = a - b;
    for (var k = 0u; k < 3u; k++) {
        if periodic_axis(k) {
            d[k] -= fluid.extent[k] * round(d[k] / fluid.extent[k]);
        }
    }
    return d;
}

// A position moved back into the domain along periodic axes.
fn fluid_wrap(x: vec3<f32>) -> vec3<f32> {
    var y = x;
    for (var k = 0u; k < 3u; k++) {
        let half_length = 0.5 * fluid.extent[k];
        if periodic_axis(k) {
            if y[k] >= half_length {
                y[k] -= fluid.extent[k];
            } else if y[k] < -half_length {
                y[k] += fluid.extent[k];
            }
        }
    }
    return y;
}

// The first neighbouring cell along axis k of cell c and how many there are: c − 1 to c + 1
// within a closed axis, each cell once along a periodic one (wrapped by `wrap_cell`).
fn cell_span(c: i32, k: u32) -> vec2<i32> {
    let n = i32(fluid.dims[k]);
    if periodic_axis(k) {
        if n >= 3 {
            return vec2<i32>(c - 1, 3);
        }
        return vec2<i32>(0, n);
    }
    let first = max(c - 1, 0);
    return vec2<i32>(first, min(c + 1, n - 1) - first + 1);
}

fn wrap_cell(c: i32, k: u32) -> i32 {
    let n = i32(fluid.dims[k]);
    return (c + n) % n;
}

// The Tait equation of state.
fn tait_pressure(rho: f32) -> f32 {
    let x = rho * fluid.eos.z;
    let x3 = x * x * x;
    return fluid.eos.y * (x3 * x3 * x - 1.0);
}

fn tait_density(p: f32) -> f32 {
    let base = p / fluid.eos.y + 1.0;
    if base <= 0.0 {
        return 0.0;
    }
    return fluid.eos.x * pow(base, 1.0 / 7.0);
}

// The Wendland C2 kernel at q = r/h: W and (dW/dr)/r, zero beyond 2h.
fn wendland(r: f32) -> vec2<f32> {
    let q = r * fluid.kernel.y;
    let s = max(1.0 - 0.5 * q, 0.0);
    let s2 = s * s;
    return vec2<f32>(fluid.kernel.w * s2 * s2 * (2.0 * q + 1.0), fluid.kernel.z * s2 * s);
}
