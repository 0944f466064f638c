// Test harness of polyhedra.wgsl and volume_contact.wgsl (shapes::evaluate): one invocation per
// query, the answer is tumble-geom's PolyContact (normal, depth, point) or VolumeContact in f32.

struct Query {
    // (kind: QUERY_POLYHEDRA, QUERY_SPHERE, QUERY_WALL, QUERY_VOLUME_PAIR or QUERY_VOLUME_WALL;
    // shape a; shape b; sphere radius)
    head: vec4<f32>,
    pos_a: vec4<f32>,
    quat_a: vec4<f32>,
    pos_b: vec4<f32>,
    quat_b: vec4<f32>,
    wall: array<vec4<f32>, WALL_ENTRY_WORDS>,
}

// Bindings: tumble-shaders' bindings.rs (POLYHEDRA_TEST).

fn shape_word(i: u32) -> vec4<f32> {
    return shapes[i];
}

// volume_points' loads: Σ weight × depth × gradient and how many.
var<private> harness_loads: vec4<f32>;

fn point_load(p: vec3<f32>, depth: f32, g: vec3<f32>, weight: f32) {
    harness_loads += vec4<f32>(weight * depth * g, 1.0);
}

@compute @workgroup_size(WORKGROUP)
fn evaluate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= count.x {
        return;
    }
    let c = queries[i];
    let kind = u32(c.head.x);
    let base = ANSWER_WORDS * i;
    if kind == QUERY_VOLUME_PAIR || kind == QUERY_VOLUME_WALL {
        var v: VolumeHit;
        var origin = vec3<f32>(0.0);
        if kind == QUERY_VOLUME_PAIR {
            v = volume_pair(u32(c.head.y), c.quat_a, u32(c.head.z), c.quat_b, c.pos_a.xyz - c.pos_b.xyz, shape_edge_density(u32(c.head.z)));
            origin = c.pos_b.xyz;
        } else {
            v = volume_wall(u32(c.head.y), c.quat_a, c.pos_a.xyz, c.wall);
        }
        harness_loads = vec4<f32>(0.0);
        if v.hit {
            volume_points();
        }
        // A cylinder's point-loads-only contact without loads is no contact.
        answers[base] = vec4<f32>(v.push, select(0.0, 1.0, v.hit && (v.volume > 0.0 || harness_loads.w > 0.0)));
        answers[base + 1u] = vec4<f32>(origin + v.point, v.depth);
        answers[base + 2u] = vec4<f32>(v.turn_a, v.volume);
        answers[base + 3u] = vec4<f32>(v.turn_b, v.area);
        answers[base + 4u] = harness_loads;
        return;
    }
    var hit: PolyHit;
    var origin = vec3<f32>(0.0);
    switch kind {
        case QUERY_POLYHEDRA: {
            hit = polyhedron_polyhedron(u32(c.head.y), c.quat_a, u32(c.head.z), c.quat_b, c.pos_a.xyz - c.pos_b.xyz);
            origin = c.pos_b.xyz;
        }
        case QUERY_SPHERE: {
            hit = sphere_polyhedron(c.head.w, u32(c.head.z), c.quat_b, c.pos_a.xyz - c.pos_b.xyz);
            origin = c.pos_b.xyz;
        }
        case QUERY_WALL: {
            hit = polyhedron_wall(u32(c.head.y), c.quat_a, c.pos_a.xyz, c.wall);
        }
        default: {
            hit = no_poly_hit();
        }
    }
    answers[base] = vec4<f32>(hit.normal, select(0.0, 1.0, hit.hit));
    answers[base + 1u] = vec4<f32>(origin + hit.point, hit.depth);
    answers[base + 2u] = vec4<f32>(hit.spread, 0.0, 0.0, 0.0);
    answers[base + 3u] = vec4<f32>(0.0);
    answers[base + 4u] = vec4<f32>(0.0);
}
