// The fluid's counting sort by cell, once per step (bindings: bindings.rs, SPH_SORT):
//
// fluid_bin          the cell of each particle and the cells' counts (u32 atomics: exact)
// (scan.wgsl turns the counts into cell starts)
// fluid_scatter      each particle takes a place in its cell's range (u32 atomics)
// fluid_order_cells  every cell's range sorted by slot, so the order never depends on timing
// fluid_permute      the particle arrays into cell order (the host copies them back), each
//                    particle's cell in tags.w

@compute @workgroup_size(WORKGROUP)
fn fluid_bin(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = fluid_index(gid);
    if i >= fluid.counts.x {
        return;
    }
    let c = cell_number(cell_coords(pos[i].xyz));
    cell[i] = c;
    atomicAdd(&count[c], 1u);
}

@compute @workgroup_size(WORKGROUP)
fn fluid_scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = fluid_index(gid);
    if i >= fluid.counts.x {
        return;
    }
    let c = cell[i];
    cell_list[cell_start[c] + atomicAdd(&cursor[c], 1u)] = i;
}

@compute @workgroup_size(WORKGROUP)
fn fluid_order_cells(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = fluid_index(gid);
    if c >= fluid.counts.y {
        return;
    }
    order_cell_range(cell_start[c], cell_start[c + 1u]);
}

@compute @workgroup_size(WORKGROUP)
fn fluid_permute(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = fluid_index(gid);
    if k >= fluid.counts.x {
        return;
    }
    let j = cell_list[k];
    pos_sorted[k] = pos[j];
    vel_sorted[k] = vel[j];
    var m = tags[j];
    m.w = cell[j];
    tags_sorted[k] = m;
}
