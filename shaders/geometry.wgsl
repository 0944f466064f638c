// Sphere–wall proximity (tumble-geom's plane, quad and cylinder in f32) and
// the periodic minimum image. Prepended to forces.wgsl.
//
// Wall table entry (WALL_ENTRY_WORDS vec4 per wall; integers as exact f32, read with u32()):
//   w0 = (kind: WALL_PLANE, WALL_QUAD, WALL_CYLINDER or WALL_PRISM; material; two-sided / inside
//         flag (0 or 1); the first index of the wall's extras, walls_moving.wgsl)
//   plane:    w1 = point, w5 = unit normal
//   quad:     w1..w4 = corners, w5 = unit normal
//   cylinder: w1 = point on the axis, w2 = unit axis, w3 = (radius, length)
//   prism:    its geometry is in its extras (walls_moving.wgsl)

struct Proximity {
    hit: bool,
    // Unit normal from the surface towards the sphere centre.
    normal: vec3<f32>,
    overlap: f32,
    point: vec3<f32>,
}

fn no_proximity() -> Proximity {
    return Proximity(false, vec3<f32>(0.0), 0.0, vec3<f32>(0.0));
}

fn surface_contact(normal: vec3<f32>, overlap: f32, point: vec3<f32>, reach: f32) -> Proximity {
    if overlap > -reach {
        return Proximity(true, normal, overlap, point);
    }
    return no_proximity();
}

fn plane_proximity(point: vec3<f32>, normal: vec3<f32>, centre: vec3<f32>, radius: f32, reach: f32) -> Proximity {
    let h = dot(normal, centre - point);
    let overlap = radius - h;
    return surface_contact(normal, overlap, centre - normal * (h + 0.5 * max(overlap, 0.0)), reach);
}

fn closest_on_segment(a: vec3<f32>, b: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let ab = b - a;
    let t = clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
    return a + ab * t;
}

fn contact_from_closest(centre: vec3<f32>, radius: f32, reach: f32, closest: vec3<f32>, fallback: vec3<f32>) -> Proximity {
    let d = centre - closest;
    let dist = length(d);
    let overlap = radius - dist;
    if overlap <= -reach {
        return no_proximity();
    }
    var normal = fallback;
    if dist > 1e-12 * radius {
        normal = d / dist;
    }
    return Proximity(true, normal, overlap, closest - normal * (0.5 * max(overlap, 0.0)));
}

fn quad_proximity(base: u32, centre: vec3<f32>, radius: f32, reach: f32) -> Proximity {
    let two_sided = tables[base].z != 0.0;
    let c0 = tables[base + 1u].xyz;
    let n = tables[base + 5u].xyz;
    let h = dot(n, centre - c0);
    if abs(h) >= radius + reach || (!two_sided && h <= -radius) {
        return no_proximity();
    }
    let foot = centre - n * h;
    var side = n;
    if two_sided && h < 0.0 {
        side = -n;
    }
    var inside = true;
    for (var k = 0u; k < 4u; k++) {
        let p = tables[base + 1u + k].xyz;
        let q = tables[base + 1u + (k + 1u) % 4u].xyz;
        inside = inside && dot(cross(q - p, foot - p), n) >= 0.0;
    }
    if inside {
        let overlap = radius - dot(side, centre - c0);
        return surface_contact(side, overlap, foot - side * (0.5 * max(overlap, 0.0)), reach);
    }
    // Edge or corner region: a one-sided quad is not touched from behind.
    if !two_sided && h <= 0.0 {
        return no_proximity();
    }
    var closest = closest_on_segment(c0, tables[base + 2u].xyz, centre);
    var best = dot(closest - centre, closest - centre);
    for (var k = 1u; k < 4u; k++) {
        let c = closest_on_segment(tables[base + 1u + k].xyz, tables[base + 1u + (k + 1u) % 4u].xyz, centre);
        let d2 = dot(c - centre, c - centre);
        if d2 < best {
            best = d2;
            closest = c;
        }
    }
    return contact_from_closest(centre, radius, reach, closest, side);
}

fn cylinder_proximity(base: u32, centre: vec3<f32>, radius: f32, reach: f32) -> Proximity {
    let inside = tables[base].z != 0.0;
    let point = tables[base + 1u].xyz;
    let axis = tables[base + 2u].xyz;
    let shell = tables[base + 3u].x;
    let rel = centre - point;
    let s = dot(rel, axis);
    if s < 0.0 || s > tables[base + 3u].y {
        return no_proximity();
    }
    let radial = rel - axis * s;
    let rho = length(radial);
    if rho < 1e-12 * shell {
        return no_proximity();
    }
    let out = radial / rho;
    var normal = out;
    var overlap = radius - (rho - shell);
    if inside {
        normal = -out;
        overlap = radius - (shell - rho);
    }
    return surface_contact(normal, overlap, point + axis * s + out * shell - normal * (0.5 * max(overlap, 0.0)), reach);
}

// The wall's kind code (w0.x).
fn wall_kind(base: u32) -> u32 {
    return u32(tables[base].x);
}

// The wall's material index (w0.y).
fn wall_material(base: u32) -> u32 {
    return u32(tables[base].y);
}

// A sphere against the wall at `base`; a kind this code does not know touches nothing.
fn wall_proximity(base: u32, centre: vec3<f32>, radius: f32, reach: f32) -> Proximity {
    switch wall_kind(base) {
        case WALL_PLANE: {
            return plane_proximity(tables[base + 1u].xyz, tables[base + 5u].xyz, centre, radius, reach);
        }
        case WALL_QUAD: {
            return quad_proximity(base, centre, radius, reach);
        }
        case WALL_CYLINDER: {
            return cylinder_proximity(base, centre, radius, reach);
        }
        case WALL_PRISM: {
            if PRISMS {
                return prism_proximity(base, centre, radius, reach);
            }
            return no_proximity();
        }
        default: {
            return no_proximity();
        }
    }
}

fn minimum_image(d_in: vec3<f32>) -> vec3<f32> {
    var d = d_in;
    for (var k = 0; k < 3; k++) {
        if params.periodic[k] != 0u {
            let l = params.extent[k];
            if d[k] > 0.5 * l {
                d[k] -= l;
            } else if d[k] < -0.5 * l {
                d[k] += l;
            }
        }
    }
    return d;
}
