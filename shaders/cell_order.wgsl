// The last step of the counting sort, shared by the particles' and the fluid's broad phases:
// a cell's range of `cell_list` sorted by slot (insertion sort; a cell holds few), so the order
// never depends on the timing of the atomics that placed them.

fn order_cell_range(start: u32, end: u32) {
    for (var k = start + 1u; k < end; k++) {
        let v = cell_list[k];
        var m = k;
        while m > start && cell_list[m - 1u] > v {
            cell_list[m] = cell_list[m - 1u];
            m--;
        }
        cell_list[m] = v;
    }
}
