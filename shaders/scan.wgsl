// Exclusive prefix sum of u32, reduce-then-scan over blocks of SCAN_BLOCK values:
//
// reduce      the total of each block into `sums`
// (the host scans `sums` the same way, level by level, until one block is left)
// scan_block  exclusive scan inside each block, plus the block's scanned total
//             from `sums` when scan.offsets is 1
//
// No decoupled look-back and no inter-workgroup communication inside a
// dispatch: nothing depends on forward-progress guarantees.

// One level of the scan (tumble-gpu's upload::ScanParams).
struct ScanParams {
    // Values at this level.
    n: u32,
    // 1 when `sums` holds block offsets.
    offsets: u32,
    // Threads per dispatch row.
    row: u32,
    _pad: u32,
}

// SCAN_THREADS, SCAN_PER_THREAD and SCAN_BLOCK come from the prelude; bindings: bindings.rs (SCAN).

var<workgroup> shared_sums: array<u32, SCAN_THREADS>;

fn block_index(wid: vec3<u32>) -> u32 {
    return wid.x + wid.y * (scan.row / SCAN_THREADS);
}

fn load(k: u32) -> u32 {
    if k < scan.n {
        return data[k];
    }
    return 0u;
}

@compute @workgroup_size(SCAN_THREADS)
fn reduce(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let block = block_index(wid);
    let base = block * SCAN_BLOCK + lid * SCAN_PER_THREAD;
    var total = 0u;
    for (var k = 0u; k < SCAN_PER_THREAD; k++) {
        total += load(base + k);
    }
    shared_sums[lid] = total;
    workgroupBarrier();
    for (var stride = SCAN_THREADS / 2u; stride > 0u; stride = stride / 2u) {
        if lid < stride {
            shared_sums[lid] += shared_sums[lid + stride];
        }
        workgroupBarrier();
    }
    if lid == 0u && block * SCAN_BLOCK < scan.n {
        sums[block] = shared_sums[0];
    }
}

@compute @workgroup_size(SCAN_THREADS)
fn scan_block(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let block = block_index(wid);
    let base = block * SCAN_BLOCK + lid * SCAN_PER_THREAD;
    var local: array<u32, SCAN_PER_THREAD>;
    var total = 0u;
    for (var k = 0u; k < SCAN_PER_THREAD; k++) {
        local[k] = total;
        total += load(base + k);
    }
    shared_sums[lid] = total;
    workgroupBarrier();
    // Hillis–Steele inclusive scan of the thread totals.
    for (var stride = 1u; stride < SCAN_THREADS; stride = stride * 2u) {
        var add = 0u;
        if lid >= stride {
            add = shared_sums[lid - stride];
        }
        workgroupBarrier();
        shared_sums[lid] += add;
        workgroupBarrier();
    }
    var offset = shared_sums[lid] - total;
    if scan.offsets == 1u && block * SCAN_BLOCK < scan.n {
        offset += sums[block];
    }
    for (var k = 0u; k < SCAN_PER_THREAD; k++) {
        if base + k < scan.n {
            data[base + k] = offset + local[k];
        }
    }
}
