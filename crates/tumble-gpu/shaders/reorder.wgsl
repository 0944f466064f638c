// Re-sorts one per-particle array into cell order: dst[k] = src[cell_list[k]].
// Every per-particle array is an array of 16-byte elements, so this one kernel
// serves them all (f32 data is moved as raw bits).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> cell_list: array<u32>;
@group(0) @binding(2) var<storage, read> src: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read_write> dst: array<vec4<u32>>;

@compute @workgroup_size(WORKGROUP)
fn permute(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = flat_index(gid);
    if k >= params.counts.x {
        return;
    }
    dst[k] = src[cell_list[k]];
}
