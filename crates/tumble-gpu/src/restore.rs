//! Snapshots of the device's own memory and continuing from them: every buffer the steps
//! read or write, byte for byte, so a run restored on the same adapter goes on bit-identically.

use crate::GpuSimulation;
use crate::readback::DeviceArrays;
use std::borrow::Cow;
use tumble_state::{DeviceImage, Fault, SNAPSHOT_VERSION, Snapshot, SnapshotError, WallState};

impl GpuSimulation {
    /// Every buffer whose contents carry over from one step to the next, named, in a fixed
    /// order. The uniform `params` and the wall stage (rewritten before each batch) are not.
    fn persistent_buffers(&self) -> Vec<(String, &wgpu::Buffer)> {
        persistent(&self.buffers)
    }

    /// The run between two steps: the device image (one read-back of every persistent buffer)
    /// and, beside it, the particles in id order widened to f64 for other readers.
    pub fn snapshot(&self) -> Snapshot {
        let buffers = self.persistent_buffers();
        let parts: Vec<(&wgpu::Buffer, u64)> = buffers.iter().map(|(_, b)| (*b, b.size())).collect();
        let bytes = self.read_bytes(&parts);
        // The frame beside the image comes from the same bytes: the prefixes a frame reads.
        let prefix = |buffer: &wgpu::Buffer, len: u64| {
            let k = buffers.iter().position(|(_, b)| std::ptr::eq(*b, buffer)).expect("a frame reads persistent buffers only");
            &bytes[k][..len as usize]
        };
        let arrays = DeviceArrays::from_bytes(self.array_parts().map(|(buffer, len)| prefix(buffer, len)));
        let load = prefix(&self.buffers.wall_load, self.wall_load_bytes());
        let work = prefix(&self.buffers.wall_work, self.wall_entry_bytes(8));
        let frame = self.frame_from(&arrays, load, work, true);
        let device = DeviceImage {
            adapter: self.adapter().to_string(),
            buffers: buffers.into_iter().map(|(name, _)| name).zip(bytes).collect(),
            counters: vec![
                ("slots".into(), self.slots as u64),
                ("generation".into(), self.generation),
                ("created".into(), self.created as u64),
                ("grid x".into(), self.grid.dims[0] as u64),
                ("grid y".into(), self.grid.dims[1] as u64),
                ("grid z".into(), self.grid.dims[2] as u64),
            ],
        };
        Snapshot {
            version: SNAPSHOT_VERSION,
            scene: self.plan().run.name.clone(),
            dt: self.plan().model.dt,
            backend: "gpu".into(),
            precision: "f32".into(),
            step: self.steps(),
            time: self.time(),
            removed: self.removed() as u64,
            outlets: self.outlet_tallies(),
            state: self.with_springs(frame.state.map(Cow::into_owned).unwrap_or_default()),
            last_pass: Vec::new(),
            walls: WallState {
                time: self.wall_time,
                built_at: self.wall_time,
                power: frame.wall_power,
                work: frame.wall_work,
                work_compensation: Vec::new(),
                servos: Vec::new(),
                wear: Vec::new(),
            },
            neighbours: None,
            last_resort: self.last_resort,
            fault: self.history_overflow().map(Fault::from),
            rng: Vec::new(),
            external: Vec::new(),
            device: Some(device),
        }
    }

    /// `state` (particles in id order) with the device's springs widened to f64, keyed by id
    /// as the CPU keys them: what another backend seeded from this snapshot takes.
    fn with_springs(&self, mut state: tumble_state::State) -> tumble_state::State {
        let slots = crate::upload::history_slots(&self.plan);
        if slots == 0 {
            return state;
        }
        let index: std::collections::HashMap<u32, usize> = state.id.iter().enumerate().map(|(i, &id)| (id, i)).collect();
        let mut history = tumble_state::HistorySlots::new(state.len(), slots, false);
        for ((owner, key), (xi, energy)) in self.stored_springs() {
            let Some(&i) = index.get(&owner) else { continue };
            let used = history.count[i] as usize;
            if used < slots {
                let xi = glam::DVec3::new(f32::from_bits(xi[0]) as f64, f32::from_bits(xi[1]) as f64, f32::from_bits(xi[2]) as f64);
                history.key[i * slots + used] = key;
                history.spring[i * slots + used] = tumble_state::TangentialHalf { xi, energy: f32::from_bits(energy) as f64 };
                history.count[i] += 1;
            }
        }
        state.history = history;
        state
    }

    /// Continues from a snapshot this backend wrote for the same scene. On the adapter that
    /// wrote it the next steps are bit-identical to the original run's; a refused snapshot
    /// changes nothing.
    pub fn restore(&mut self, snap: &Snapshot) -> Result<(), SnapshotError> {
        snap.check_fits(self.plan())?;
        if snap.backend != "gpu" {
            return Err(SnapshotError::Mismatch(format!("written by the {} backend; restore it there", snap.backend)));
        }
        let image = snap.device.as_ref().ok_or_else(|| SnapshotError::Corrupt("a GPU snapshot without its device image".into()))?;
        let slots = image.counter("slots").ok_or_else(|| SnapshotError::Corrupt("the device image has no slot count".into()))?;
        let generation = image.counter("generation").ok_or_else(|| SnapshotError::Corrupt("the device image has no history generation".into()))?;
        let created = image.counter("created").ok_or_else(|| SnapshotError::Corrupt("the device image has no count of the ids given".into()))?;
        if slots > u32::MAX as u64 / 2 || created > slots || snap.state.id.iter().any(|&id| id as u64 >= created) {
            return Err(SnapshotError::Corrupt(format!(
                "the device image gave {created} ids, more than its {slots} slots or fewer than its particles"
            )));
        }
        let dims = match (image.counter("grid x"), image.counter("grid y"), image.counter("grid z")) {
            (Some(x), Some(y), Some(z)) if [x, y, z].iter().all(|&d| (1..=1 << 20).contains(&d)) => [x as u32, y as u32, z as u32],
            // Written before images named their grid: the buffer sizes below still check it.
            (None, None, None) => self.grid.dims,
            _ => return Err(SnapshotError::Corrupt("the device image has no valid cell grid".into())),
        };
        // The run grew (sources) or was planned for another duration: match its slots and grid first.
        let grid = crate::upload::Grid::with_dims(self.plan(), dims);
        let resized = if slots != self.slots as u64 || grid != self.grid {
            Some(
                self.resized(slots as u32, grid)
                    .map_err(|e| SnapshotError::Mismatch(format!("its {slots} particle slots do not fit on this device: {e}")))?,
            )
        } else {
            None
        };
        let buffers = persistent(resized.as_ref().map_or(&self.buffers, |r| &r.buffers));
        // Check everything before writing anything.
        let mut writes = Vec::with_capacity(buffers.len());
        for (name, buffer) in &buffers {
            let bytes = image.buffer(name).ok_or_else(|| SnapshotError::Mismatch(format!("the device image has no `{name}` buffer")))?;
            if bytes.len() as u64 != buffer.size() {
                return Err(SnapshotError::Mismatch(format!(
                    "its `{name}` buffer holds {} bytes, this run's {} (another model or grid)",
                    bytes.len(),
                    buffer.size()
                )));
            }
            writes.push(((*buffer).clone(), bytes));
        }
        if image.buffers.len() != buffers.len() {
            return Err(SnapshotError::Mismatch(format!("the device image has {} buffers, this run {}", image.buffers.len(), buffers.len())));
        }
        drop(buffers);
        if let Some(r) = resized {
            self.commit(r);
        }
        for (buffer, bytes) in writes {
            self.gpu.queue.write_buffer(&buffer, 0, bytes);
        }
        self.gpu.queue.submit([]);
        self.wait();
        self.step = snap.step;
        self.generation = generation;
        self.created = created as u32;
        *self.departed.borrow_mut() = None;
        *self.waiting.borrow_mut() = None;
        // Inserted particles' groups (the device does not keep them).
        for (&id, &g) in snap.state.id.iter().zip(&snap.state.group) {
            self.group[id as usize] = g;
        }
        self.last_resort = snap.last_resort;
        self.wall_time = snap.walls.time;
        self.pending_walls.clear();
        self.overflow.set(snap.fault.map(|Fault::HistoryOverflow(o)| o));
        self.alive.set(None);
        Ok(())
    }
}

/// Every buffer whose contents carry over from one step to the next, named, in a fixed order.
fn persistent(b: &crate::buffers::Buffers) -> Vec<(String, &wgpu::Buffer)> {
    let mut out: Vec<(String, &wgpu::Buffer)> = [
        ("pos", &b.pos),
        ("vel", &b.vel),
        ("omega", &b.omega),
        ("acc", &b.acc),
        ("alpha", &b.alpha),
        ("props", &b.props),
        ("energy", &b.energy),
        ("force", &b.force),
        ("torque", &b.torque),
        ("stats", &b.stats),
        ("scratch", &b.scratch),
        ("cell", &b.cell),
        ("cell_list", &b.cell_list),
        ("count", &b.count),
        ("cursor", &b.cursor),
        ("cell_start", &b.cell_start),
        ("tables", &b.tables),
        ("orient", &b.orient),
        ("image", &b.image),
        ("history a", &b.history[0]),
        ("history b", &b.history[1]),
        ("wall_load", &b.wall_load),
        ("wall_work", &b.wall_work),
    ]
    .into_iter()
    .map(|(name, buffer)| (name.to_string(), buffer))
    .collect();
    out.extend(b.scan_levels.iter().enumerate().map(|(k, buffer)| (format!("scan level {}", k + 1), buffer)));
    out
}
