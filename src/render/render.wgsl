// Pictures of a run (src/render/gpu.rs): spheres as impostors, walls and polyhedra as
// triangles, in view coordinates (x right, y up, z towards the viewer) under an orthographic
// projection. The host moves every point into view coordinates in f64 first.

struct View {
    // 1 / half width, 1 / half height, half depth range, unused.
    scale: vec4<f32>,
    // Unit direction towards the light, view coordinates.
    light: vec4<f32>,
}

// Shading: ambient + diffuse · max(n · light, 0); they sum to one, so a surface facing the light
// shows its colour-map colour exactly.
const AMBIENT: f32 = 0.35;
const DIFFUSE: f32 = 0.65;

@group(0) @binding(0) var<uniform> view: View;
// Per sphere two entries: (centre, radius) and (colour, 1).
@group(0) @binding(1) var<storage, read> spheres: array<vec4<f32>>;
// Per triangle or line corner three entries: (position, 1), (unit face normal, 0) or, unshaded
// (lines), (0, 0, 0, 1), and (colour, alpha).
@group(0) @binding(2) var<storage, read> corners: array<vec4<f32>>;

// Depth 0 at the nearest point of the frame's box, 1 at the farthest.
fn depth_of(z: f32) -> f32 {
    return (view.scale.z - z) / (2.0 * view.scale.z);
}

fn clip_of(p: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(p.xy * view.scale.xy, depth_of(p.z), 1.0);
}

struct SphereCorner {
    @builtin(position) clip: vec4<f32>,
    // Where the corner lies on the sphere's square, in radii.
    @location(0) offset: vec2<f32>,
    @location(1) @interpolate(flat) sphere: vec4<f32>,
    @location(2) @interpolate(flat) colour: vec4<f32>,
}

// Six corners (two triangles) of the square that just covers sphere `instance` on screen.
@vertex
fn sphere_corner(@builtin(vertex_index) corner: u32, @builtin(instance_index) instance: u32) -> SphereCorner {
    var square = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let sphere = spheres[2u * instance];
    let offset = square[corner];
    var out: SphereCorner;
    out.clip = clip_of(vec3<f32>(sphere.xy + offset * sphere.w, sphere.z + sphere.w));
    out.offset = offset;
    out.sphere = sphere;
    out.colour = spheres[2u * instance + 1u];
    return out;
}

struct SphereFragment {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// The visible surface point under the pixel: its depth and its Lambert shade; outside the disc nothing.
@fragment
fn sphere_surface(input: SphereCorner) -> SphereFragment {
    let rr = dot(input.offset, input.offset);
    if rr > 1.0 {
        discard;
    }
    let normal = vec3<f32>(input.offset, sqrt(1.0 - rr));
    var out: SphereFragment;
    out.depth = depth_of(input.sphere.z + input.sphere.w * normal.z);
    let shade = AMBIENT + DIFFUSE * max(dot(normal, view.light.xyz), 0.0);
    out.colour = vec4<f32>(input.colour.rgb * shade, 1.0);
    return out;
}

struct SurfaceCorner {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour: vec4<f32>,
}

// A triangle corner, shaded flat and from either side (walls are seen from inside and out).
@vertex
fn surface_corner(@builtin(vertex_index) corner: u32) -> SurfaceCorner {
    let position = corners[3u * corner];
    let normal = corners[3u * corner + 1u];
    let colour = corners[3u * corner + 2u];
    var out: SurfaceCorner;
    out.clip = clip_of(position.xyz);
    let shade = select(AMBIENT + DIFFUSE * abs(dot(normal.xyz, view.light.xyz)), 1.0, normal.w > 0.5);
    out.colour = vec4<f32>(colour.rgb * shade, colour.a);
    return out;
}

@fragment
fn surface_fill(input: SurfaceCorner) -> @location(0) vec4<f32> {
    return input.colour;
}
