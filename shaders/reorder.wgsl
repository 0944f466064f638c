// Re-sorts one per-particle array into cell order: dst[k] = src[cell_list[k]].
// Every per-particle array is an array of 16-byte elements, so this one kernel
// serves them all (f32 data is moved as raw bits). Bindings: bindings.rs (REORDER).

@compute @workgroup_size(WORKGROUP)
fn permute(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = flat_index(gid);
    if k >= params.particles {
        return;
    }
    dst[k] = src[cell_list[k]];
}
