// The output row's reductions on the device (tumble-gpu's reduce.rs): the particle sums
// as a fixed-shape tree (each workgroup reduces REDUCE_BLOCK values into one partial, then
// the partials are reduced the same way until one is left; no float atomics, so every run
// sums in the same order), and the tracked particles gathered into rows by rank.
// Bindings: bindings.rs (REDUCE).
//
// Each level runs one workgroup row per lane (workgroup_id.z): lane 0 the observables, then
// one per wall group (its power and work), then one per drum (its charge mass and Σ m·radial,
// and the shell layer's angle histogram in integer counts).
//
// Energies are two-float (hi, lo) terms and sums: each operation keeps its rounding error
// in lo where the compiler keeps IEEE order (lavapipe's folds it away, leaving f32 terms
// summed pairwise; tumble-gpu's reduce.rs states the accuracy).

// One level's inputs and partials.
struct ReduceParams {
    // Values this level reduces per lane (slots at level 0, partials above).
    inputs: u32,
    // Partials it writes per lane (one per workgroup).
    groups: u32,
    // Materials per shape row of the inertia table.
    materials: u32,
    // Lanes: 1 + wall groups (with WALLS) + drums.
    lanes: u32,
    wall_groups: u32,
    drums: u32,
    // First vec4 of the drum rows in reduce_table.
    drum_rows: u32,
    // 1 at level 0 (inputs are slots), 0 above (inputs are partials).
    first: u32,
    // Gravity as two-float (hi, lo) per axis (the host's is f64).
    gravity_hi: vec4<f32>,
    gravity_lo: vec4<f32>,
}

// The sums of a range of slots in one lane (tumble-gpu's reduce::Partial, field for field).
struct Partial {
    // (hi, lo) pairs. Lane 0: kinetic, rotational, potential (relative to the device origin),
    // movable mass (the host adds the origin's potential with it), elastic, dissipated,
    // fluid work, unused. A wall group: power, work, force (x, y, z), torque about the device's
    // origin (x, y, z). A drum: charge mass, Σ m·radial (x, y, z).
    sums: array<vec2<f32>, 8>,
    // Lane 0: contacts, largest overlap ratio (f32 bits), finite (1 or 0), particles in the domain.
    counts: vec4<u32>,
}

const REDUCE_KINETIC: u32 = 0u;
const REDUCE_ROTATIONAL: u32 = 1u;
const REDUCE_POTENTIAL: u32 = 2u;
const REDUCE_MASS: u32 = 3u;
const REDUCE_ELASTIC: u32 = 4u;
const REDUCE_DISSIPATED: u32 = 5u;
const REDUCE_FLUID: u32 = 6u;

var<workgroup> reduce_shared: array<Partial, WORKGROUP>;

// Two-float arithmetic: a value is hi + lo with |lo| ≤ ½ ulp(hi), about 48 bits. Each
// term is formed this way as well as summed, so a sum is close to the host's f64 one.

// a + b (TwoSum of the high parts, the low parts and the error renormalised into the pair).
fn tf_add(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let s = a.x + b.x;
    let v = s - a.x;
    let e = (a.x - (s - v)) + (b.x - v);
    return tf_renormalise(s, e + a.y + b.y);
}

// s + e as a pair, for |e| small against |s|.
fn tf_renormalise(s: f32, e: f32) -> vec2<f32> {
    let hi = s + e;
    return vec2<f32>(hi, e - (hi - s));
}

// a b exactly (the error of the rounded product by fma; an adapter whose fma rounds twice
// loses only the compensation).
fn tf_product(a: f32, b: f32) -> vec2<f32> {
    let p = a * b;
    return vec2<f32>(p, fma(a, b, -p));
}

fn tf_mul_f(a: vec2<f32>, b: f32) -> vec2<f32> {
    let p = tf_product(a.x, b);
    return tf_renormalise(p.x, p.y + a.y * b);
}

fn tf_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let p = tf_product(a.x, b.x);
    return tf_renormalise(p.x, p.y + (a.x * b.y + a.y * b.x));
}

fn tf_div_f(a: vec2<f32>, d: f32) -> vec2<f32> {
    let q = a.x / d;
    let r = tf_add(a, -tf_product(q, d));
    return tf_renormalise(q, r.x / d);
}

// a · b of f32 vectors.
fn tf_dot(a: vec3<f32>, b: vec3<f32>) -> vec2<f32> {
    return tf_add(tf_add(tf_product(a.x, b.x), tf_product(a.y, b.y)), tf_product(a.z, b.z));
}

// a · b of a two-float vector (hi, lo per axis) and an f32 one.
fn tf_dot_tf(a_hi: vec3<f32>, a_lo: vec3<f32>, b: vec3<f32>) -> vec2<f32> {
    var s = vec2<f32>(0.0);
    for (var k = 0u; k < 3u; k++) {
        s = tf_add(s, tf_mul_f(vec2<f32>(a_hi[k], a_lo[k]), b[k]));
    }
    return s;
}

// Axis k of q⁻¹ v for the host's glam formula, v (w² − b·b) + b 2(v·b) + (b × v) 2w with
// b = −q.xyz (the host rotates by the conjugate), in two-float.
fn tf_body_axis(q: vec4<f32>, v: vec3<f32>, k: u32) -> vec2<f32> {
    let b = -q.xyz;
    let scale = tf_add(tf_product(q.w, q.w), -tf_dot(b, b));
    let along = tf_dot(v, b);
    let i = (k + 1u) % 3u;
    let j = (k + 2u) % 3u;
    let b_cross_v = tf_add(tf_product(b[i], v[j]), -tf_product(b[j], v[i]));
    let out = tf_add(tf_mul_f(scale, v[k]), tf_mul_f(along, 2.0 * b[k]));
    return tf_add(out, tf_mul_f(b_cross_v, 2.0 * q.w));
}

fn empty_partial() -> Partial {
    var p: Partial;
    p.counts = vec4<u32>(0u, 0u, 1u, 0u);
    return p;
}

fn combine(a: Partial, b: Partial) -> Partial {
    var p: Partial;
    for (var k = 0u; k < 8u; k++) {
        p.sums[k] = tf_add(a.sums[k], b.sums[k]);
    }
    p.counts = vec4<u32>(a.counts.x + b.counts.x, max(a.counts.y, b.counts.y), a.counts.z & b.counts.z, a.counts.w + b.counts.w);
    return p;
}

// Neither infinite nor NaN (by the exponent bits, which no compiler assumes away).
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn finite3(v: vec3<f32>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

// Rotational energy ½ ω·I ω of movable slot i (body-frame principal inertia for polyhedra).
fn rotational_energy(i: u32, w: vec4<f32>, shape: u32) -> vec2<f32> {
    if POLYHEDRA && shape != SPHERE_SHAPE {
        let q = orient[i];
        let row = shape * reduce_level.materials + props[i].y;
        let inertia_hi = reduce_table[2u * row];
        let inertia_lo = reduce_table[2u * row + 1u];
        var e = vec2<f32>(0.0);
        for (var k = 0u; k < 3u; k++) {
            let body = tf_body_axis(q, w.xyz, k);
            e = tf_add(e, tf_mul(tf_mul(body, body), vec2<f32>(inertia_hi[k], inertia_lo[k])));
        }
        return 0.5 * e;
    }
    // Spheres: |ω|² / (1/I); in a polyhedra scene the host's rotation to the body frame
    // changes |ω| only by its rounding.
    return 0.5 * tf_div_f(tf_dot(w.xyz, w.xyz), w.w);
}

// −g·x of slot i at its unwrapped position x + n∘L (periodic axes), in two-float: n∘L is
// formed exactly from the f32 extent, so the only error beyond the sum's is L's rounding to
// f32 (2⁻²⁴ of g·(n∘L), no larger than the summation's own; docs/chute.md).
fn potential_height(i: u32, x: vec3<f32>) -> vec2<f32> {
    let g_hi = reduce_level.gravity_hi.xyz;
    let g_lo = reduce_level.gravity_lo.xyz;
    var height = tf_dot_tf(g_hi, g_lo, x);
    if PERIODIC {
        let n = image[props[i].z].xyz;
        for (var k = 0u; k < 3u; k++) {
            if n[k] != 0 {
                let shift = tf_product(f32(n[k]), params.extent[k]);
                height = tf_add(height, tf_mul(shift, vec2<f32>(g_hi[k], g_lo[k])));
            }
        }
    }
    return height;
}

// Slot i's terms, as the host's Observables::of_particles and add_contacts take them:
// energies of movable particles only, books and contacts of every particle in the domain.
fn slot_partial(i: u32) -> Partial {
    var p = empty_partial();
    let flags = props[i].w;
    if (flags & FLAG_DEAD) != 0u {
        return p;
    }
    let x = pos[i];
    let v = vel[i];
    let f = force[i];
    let books = energy[i];
    // The host's finish() also asks the elastic and dissipated sums to be finite.
    var ok = finite3(x.xyz) && finite3(v.xyz) && finite(f.w) && finite(books.x);
    if v.w != 0.0 {
        let m = alpha[i].w;
        p.sums[REDUCE_KINETIC] = 0.5 * tf_mul_f(tf_dot(v.xyz, v.xyz), m);
        p.sums[REDUCE_POTENTIAL] = -tf_mul_f(potential_height(i, x.xyz), m);
        p.sums[REDUCE_MASS].x = m;
        if ROTATION {
            let w = omega[i];
            ok = ok && finite3(w.xyz);
            p.sums[REDUCE_ROTATIONAL] = rotational_energy(i, w, flags >> SHAPE_SHIFT);
        }
    }
    p.sums[REDUCE_ELASTIC].x = f.w;
    p.sums[REDUCE_DISSIPATED].x = books.x;
    if DRAG != DRAG_NONE {
        p.sums[REDUCE_FLUID].x = books.y;
    }
    // The host's f64 max over ratios from 0 ignores NaN and negative values.
    let ratio = stats[i].y;
    p.counts = vec4<u32>(stats[i].x, select(0u, ratio, ratio <= 0x7f800000u), u32(ok), 1u);
    return p;
}

// Slot (= particle id) i's entries of wall group g: power, work (a Kahan pair), force, torque.
fn wall_partial(i: u32, g: u32) -> Partial {
    var p = empty_partial();
    if WALLS {
        let k = i * reduce_level.wall_groups + g;
        let load = wall_load[2u * k];
        let torque = wall_load[2u * k + 1u];
        p.sums[0].x = load.w;
        for (var c = 0u; c < 3u; c++) {
            p.sums[2u + c].x = load[c];
            p.sums[5u + c].x = torque[c];
        }
    }
    if MOVING {
        let w = wall_work[i * reduce_level.wall_groups + g];
        p.sums[1] = tf_renormalise(w.x, -w.y);
    }
    return p;
}

// Slot i's share of drum d's profile (tumble-state's drum_profiles): movable particles with
// their centre inside the drum, and the shell layer's angles counted into drum_bins.
fn drum_partial(i: u32, d: u32) -> Partial {
    var p = empty_partial();
    if !MOVING || (props[i].w & FLAG_DEAD) != 0u || vel[i].w == 0.0 {
        return p;
    }
    let row = reduce_level.drum_rows + d * DRUM_ROW_WORDS;
    let point = reduce_table[row];
    let axis = reduce_table[row + 1u];
    let rel = pos[i].xyz - point.xyz;
    let z = dot(rel, axis.xyz);
    let radial = rel - axis.xyz * z;
    let rho = length(radial);
    if z < 0.0 || z > axis.w || rho > point.w {
        return p;
    }
    let m = alpha[i].w;
    p.sums[0].x = m;
    for (var k = 0u; k < 3u; k++) {
        p.sums[1u + k] = tf_product(m, radial[k]);
    }
    let r = pos[i].w;
    if point.w - rho - r <= 0.5 * r {
        let angle = degrees(atan2(dot(radial, reduce_table[row + 3u].xyz), dot(radial, reduce_table[row + 2u].xyz)));
        let bin = min(u32(max((angle + 180.0) / 360.0 * f32(DRUM_BINS), 0.0)), DRUM_BINS - 1u);
        atomicAdd(&drum_bins[d * DRUM_BINS + bin], 1u);
    }
    return p;
}

// Level 0's term of slot i in `lane`.
fn lane_partial(i: u32, lane: u32) -> Partial {
    if lane == 0u {
        return slot_partial(i);
    }
    if lane <= reduce_level.wall_groups {
        return wall_partial(i, lane - 1u);
    }
    return drum_partial(i, lane - 1u - reduce_level.wall_groups);
}

// One level in one lane: REDUCE_BLOCK inputs per workgroup (slots at level 0, the level
// below's partials above), each thread summing every WORKGROUP-th one, then the workgroup's
// partials pairwise into one.
@compute @workgroup_size(WORKGROUP)
fn reduce_rows(@builtin(local_invocation_index) lid: u32, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let group = wid.x + wid.y * nwg.x;
    let lane = wid.z;
    var acc = empty_partial();
    for (var k = 0u; k < REDUCE_BLOCK / WORKGROUP; k++) {
        let j = group * REDUCE_BLOCK + k * WORKGROUP + lid;
        if j < reduce_level.inputs {
            if reduce_level.first != 0u {
                acc = combine(acc, lane_partial(j, lane));
            } else {
                acc = combine(acc, partials_in[j * reduce_level.lanes + lane]);
            }
        }
    }
    reduce_shared[lid] = acc;
    workgroupBarrier();
    for (var stride = WORKGROUP / 2u; stride > 0u; stride = stride / 2u) {
        if lid < stride {
            reduce_shared[lid] = combine(reduce_shared[lid], reduce_shared[lid + stride]);
        }
        workgroupBarrier();
    }
    if lid == 0u && group < reduce_level.groups {
        partials_out[group * reduce_level.lanes + lane] = reduce_shared[0];
    }
}

// Each tracked particle in the domain writes its row at its rank (ranks are unique, so are
// the writes; the host clears the rows first, so a removed one reads as absent).
@compute @workgroup_size(WORKGROUP)
fn gather_tracks(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if i >= params.particles || (props[i].w & FLAG_DEAD) != 0u {
        return;
    }
    let id = props[i].z;
    let rank = track_rank[id];
    if rank == NO_TRACK {
        return;
    }
    var q = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if POLYHEDRA {
        q = orient[i];
    }
    let row = rank * TRACK_ROW_WORDS;
    tracks[row] = vec4<u32>(bitcast<vec3<u32>>(pos[i].xyz), id);
    tracks[row + 1u] = vec4<u32>(bitcast<vec3<u32>>(vel[i].xyz), 1u);
    tracks[row + 2u] = vec4<u32>(bitcast<vec3<u32>>(omega[i].xyz), 0u);
    tracks[row + 3u] = bitcast<vec4<u32>>(q);
}
