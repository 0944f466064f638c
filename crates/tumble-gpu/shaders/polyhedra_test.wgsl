// Test harness of polyhedra.wgsl (shapes::evaluate): one invocation per query,
// the answer is tumble-geom's PolyContact (normal, depth, point) in f32.

struct Query {
    // (kind: 0 polyhedra, 1 sphere, 2 wall; shape a; shape b; sphere radius)
    head: vec4<f32>,
    pos_a: vec4<f32>,
    quat_a: vec4<f32>,
    pos_b: vec4<f32>,
    quat_b: vec4<f32>,
    wall: array<vec4<f32>, 6>,
}

@group(0) @binding(0) var<uniform> count: vec4<u32>;
@group(0) @binding(1) var<storage, read> shapes: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> queries: array<Query>;
@group(0) @binding(3) var<storage, read_write> answers: array<vec4<f32>>;

fn shape_word(i: u32) -> vec4<f32> {
    return shapes[i];
}

@compute @workgroup_size(64)
fn evaluate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= count.x {
        return;
    }
    let c = queries[i];
    let kind = u32(c.head.x);
    var hit: PolyHit;
    var origin = vec3<f32>(0.0);
    if kind == 0u {
        hit = polyhedron_polyhedron(u32(c.head.y), c.quat_a, u32(c.head.z), c.quat_b, c.pos_a.xyz - c.pos_b.xyz);
        origin = c.pos_b.xyz;
    } else if kind == 1u {
        hit = sphere_polyhedron(c.head.w, u32(c.head.z), c.quat_b, c.pos_a.xyz - c.pos_b.xyz);
        origin = c.pos_b.xyz;
    } else {
        hit = polyhedron_wall(u32(c.head.y), c.quat_a, c.pos_a.xyz, c.wall);
    }
    answers[3u * i] = vec4<f32>(hit.normal, select(0.0, 1.0, hit.hit));
    answers[3u * i + 1u] = vec4<f32>(origin + hit.point, hit.depth);
    answers[3u * i + 2u] = vec4<f32>(hit.spread, 0.0, 0.0, 0.0);
}
