// Broad phase: cell index and counting sort of particle slots into cells.
//
// bin          cell of each particle, per-cell counts (u32 atomics: counts are exact)
// (scan.wgsl turns the counts into cell starts)
// scatter      each particle takes a place in its cell's range (u32 atomics)
// order_cells  sorts every cell's range by slot, so the final order never
//              depends on atomic timing: the same on every run
//
// Removed particles go to the extra bucket `cells` at the end.
// Bindings: tumble-shaders' bindings.rs (BROAD).

fn axis_cell(x: f32, inv_width: f32, cells: u32) -> u32 {
    let c = i32(floor(x * inv_width));
    return u32(clamp(c, 0, i32(cells) - 1));
}

@compute @workgroup_size(WORKGROUP)
fn bin(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if i >= params.particles {
        return;
    }
    var c = params.cells;
    if (props[i].w & FLAG_DEAD) == 0u {
        let x = pos[i].xyz + 0.5 * params.extent;
        let cx = axis_cell(x.x, params.inv_cell.x, params.dims.x);
        let cy = axis_cell(x.y, params.inv_cell.y, params.dims.y);
        let cz = axis_cell(x.z, params.inv_cell.z, params.dims.z);
        c = cx + params.dims.x * (cy + params.dims.y * cz);
    }
    cell[i] = c;
    atomicAdd(&count[c], 1u);
}

@compute @workgroup_size(WORKGROUP)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = flat_index(gid);
    if i >= params.particles {
        return;
    }
    let c = cell[i];
    cell_list[cell_start[c] + atomicAdd(&cursor[c], 1u)] = i;
}

// One invocation per cell (and the removed bucket): insertion sort of its slots.
@compute @workgroup_size(WORKGROUP)
fn order_cells(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = flat_index(gid);
    if c > params.cells {
        return;
    }
    order_cell_range(cell_start[c], cell_start[c + 1u]);
}
