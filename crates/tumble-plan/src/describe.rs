//! The plan as text: what `tumble plan` prints and summary.json keeps.

use crate::plan::{Plan, WALL_ADVANCE_FRACTION};
use std::fmt::Write as _;

impl Plan {
    /// The plan as text, for `tumble plan`.
    pub fn describe(&self, particles: usize) -> String {
        let (model, run, tuning, report) = (&self.model, &self.run, &self.tuning, &self.report);
        let ts = &report.timescales;
        let mut s = String::new();
        let _ = writeln!(s, "scene        {}", run.name);
        let _ = writeln!(s, "particles    {particles}");
        let capacity = particles + self.inserted_at_most() as usize;
        for src in &model.sources {
            let rate = match src.rate {
                Some(crate::Rate::ParticlesPerSecond(r)) => format!("{r} particles/s"),
                Some(crate::Rate::KgPerSecond(r)) => format!("{r} kg/s"),
                None => "all at once".into(),
            };
            let total = match src.total {
                Some(crate::Total::Particles(n)) => format!(" up to {n} particles"),
                Some(crate::Total::Kg(m)) => format!(" up to {m} kg"),
                None => String::new(),
            };
            let region = match &src.region {
                crate::InsertRegion::Box { .. } => "box".to_string(),
                crate::InsertRegion::Cylinder { .. } => "cylinder".to_string(),
                crate::InsertRegion::Plane { .. } => "plane".to_string(),
                crate::InsertRegion::Mesh { mesh, .. } => format!("closed mesh of {} triangles", mesh.body.mesh.triangles.len()),
            };
            let volume = if src.region.volume() > 0.0 { format!(", {:.4e} m³", src.region.volume()) } else { String::new() };
            let _ = writeln!(
                s,
                "source       {} ({region}{volume}): {rate}{total}, every {} steps ({:.4e} s) from t = {:.4e} s to {:.4e} s; mean particle {:.4e} kg; at most {} particles",
                src.name,
                src.every,
                src.every as f64 * model.dt,
                src.first_step as f64 * model.dt,
                src.last_step as f64 * model.dt,
                src.mean_mass,
                src.most_particles(model.dt)
            );
        }
        if !model.sources.is_empty() {
            let _ = writeln!(
                s,
                "capacity     {capacity} particles (those at the start and all the sources may insert); the GPU starts with {} slots and adds {} at a time as the sources need them",
                particles as u64 + self.tuning.capacity_chunk,
                self.tuning.capacity_chunk
            );
        }
        for o in &model.outlets {
            let region = match o.region {
                crate::OutletRegion::Box { min, max } => format!("the box [{min} .. {max}]"),
                crate::OutletRegion::Beyond { point, normal } => format!("the side of the plane through {point} that its normal {normal} points to"),
            };
            let _ = writeln!(s, "outlet       {}: deletes particles whose centre enters {region}", o.name);
        }
        let dem = particles > 0 || !model.sources.is_empty() || self.sph.is_none();
        if dem {
            let _ = writeln!(s, "integrator   {}", model.integrator.name());
        }
        let _ = writeln!(s, "dt           {:.6e} s ({} steps to t = {} s)", model.dt, run.steps, run.duration);
        if let Some(fluid) = &self.sph {
            describe_sph(&mut s, fluid);
            describe_coupling(&mut s, fluid, model.dt);
        }
        if !dem {
            for w in &report.warnings {
                let _ = writeln!(s, "warning: {w}");
            }
            return s;
        }
        if let Some(t) = ts.collision_time {
            let _ = writeln!(s, "t_col        {:.6e} s ({:.1} steps per collision)", t, t / model.dt);
        }
        let i = &ts.impact;
        let _ = writeln!(
            s,
            "impact       {:.4} m/s (estimate: initial {:.4} m/s, drop {:.4} m under gravity, walls {:.4} m/s; Hertz contact times and quadratic drag are taken at it)",
            i.speed, i.initial, i.drop_height, i.wall
        );
        if let Some(t) = ts.rayleigh_time {
            let _ = writeln!(s, "rayleigh     {t:.6e} s");
        }
        if let Some(t) = ts.tangential_time {
            let _ = writeln!(s, "tau_t        {t:.6e} s (viscous tangential relaxation m*_t / c_t)");
        }
        if let Some(t) = ts.drag_time {
            let _ = writeln!(s, "tau_p        {t:.6e} s (shortest drag relaxation time)");
        }
        if let Some(t) = ts.stability_limit {
            let _ = writeln!(s, "limit        {t:.6e} s (largest stable dt)");
        }
        if let Some(w) = &report.wall_step_limit {
            let _ = writeln!(
                s,
                "wall limit   {:.6e} s (moving geometry: wall \"{}\" moves at up to {:.4} m/s; dt <= {} r_min / v_wall with r_min = {:.4e} m)",
                w.dt, w.wall, w.speed, WALL_ADVANCE_FRACTION, w.r_min
            );
        }
        let _ = writeln!(s, "cell size    {:.6e} m + skin {:.3e} m, grid {:?}", tuning.cell_size, tuning.skin, self.grid_dims());
        let _ = writeln!(
            s,
            "memory       {:.1} MiB on the cpu at most ({} bytes per particle; the grid spans the particles, here the whole domain)",
            self.memory_bytes(capacity) as f64 / (1 << 20) as f64,
            tuning.bytes_per_particle
        );
        let _ = writeln!(s, "features");
        for f in &report.features {
            let _ = writeln!(s, "  {:<12} {:<4} {}", f.name, if f.active { "on" } else { "off" }, f.reason);
        }
        if let Some(tg) = &report.targets.taylor_green {
            let _ = write!(s, "taylor-green u_0 = {:.6} m/s (mean |u|), l_0 = pi/a = {:.6} m", tg.mean_flow_speed, tg.vortex_size);
            match (tg.stokes_number, tg.viscosity) {
                (Some(stk), Some(mu)) => {
                    let _ = writeln!(s, ", Stk = {stk:.6} (mu = {mu:.6e} Pa s)");
                }
                _ => {
                    let _ = writeln!(s);
                }
            }
        }
        if let Some(sy) = &report.targets.stickiness {
            let _ = writeln!(
                s,
                "stickiness   Sy = {:.6} (k_c = {:.6e} N/m, e = {}, L_e = {:.4e} m, m* = {:.4e} kg, collision speed {:.6} m/s)",
                sy.number, sy.stiffness, sy.restitution, sy.effect_length, sy.reduced_mass, sy.collision_speed
            );
        }
        for w in &report.warnings {
            let _ = writeln!(s, "warning: {w}");
        }
        s
    }
}

/// Whether the particles and the fluid act on each other, and how.
fn describe_coupling(s: &mut String, p: &crate::SphPlan, dt: f64) {
    let Some(c) = &p.coupling else { return };
    let drag = match c.drag {
        tumble_sph::coupling::DragLaw::Gidaspow => "Gidaspow (Ergun below a fluid fraction of 0.8, Wen & Yu above)",
        tumble_sph::coupling::DragLaw::DiFelice => "Di Felice",
    };
    let _ = writeln!(
        s,
        "coupling     on, as the scene has particles and a 3D fluid: unresolved SPH–DEM (Robinson et al. 2014, He et al. 2018), drag {drag}, buoyancy from the fluid's pressure; the fluid steps {:.6e} s, {} particle steps, holding the particles' fluid forces over them (at most {:.4e} s, a quarter of the particles' shortest drag relaxation time rho_p d²/(225 mu), or the fluid's dt)",
        dt * c.substeps as f64,
        c.substeps,
        c.drag_limit
    );
    if let Some(d) = c.front {
        let _ = writeln!(s, "coupling     the particles' front along [{:.3}, {:.3}, {:.3}] in coupling.csv (solid_front)", d.x, d.y, d.z);
    }
}

/// The fluid's lines: its particles, method, time-step limits and probes.
fn describe_sph(s: &mut String, p: &crate::SphPlan) {
    use tumble_sph::{DensityDiffusion, Dimension, Viscosity};
    let f = &p.settings;
    let dimension = match f.dimension {
        Dimension::Two => "2D (the x–z plane, per metre of span)",
        Dimension::Three => "3D",
    };
    let _ = writeln!(
        s,
        "fluid        SPH, {dimension}: {} fluid and {} wall particles, spacing {:.4e} m, h = {:.4e} m ({} spacings)",
        p.fluid_particles,
        p.wall_particles,
        f.spacing,
        f.h,
        f.h / f.spacing
    );
    let viscosity = match f.viscosity {
        Viscosity::Laminar => format!("laminar viscosity (Morris) mu = {:e} Pa s", f.mu),
        Viscosity::Artificial { alpha } => format!("artificial viscosity alpha = {alpha} (mu = {:e} Pa s enters dt only)", f.mu),
    };
    let diffusion = match f.density_diffusion {
        DensityDiffusion::None => "no density diffusion".to_string(),
        DensityDiffusion::MolteniColagrossi { delta } => format!("delta-SPH (Molteni-Colagrossi) delta = {delta}"),
        DensityDiffusion::Fourtakas { delta } => format!("delta-SPH (Fourtakas) delta = {delta}"),
    };
    let _ = writeln!(
        s,
        "fluid method Wendland C2; Tait rho0 = {} kg/m³, c0 = {:.4} m/s ({:.1} times the expected speed {:.4} m/s); {viscosity}; {diffusion}; tensile correction {}; XSPH {}",
        f.rho0,
        f.sound_speed,
        f.sound_speed / p.expected_speed,
        p.expected_speed,
        if f.tensile_correction { "on" } else { "off" },
        if f.xsph > 0.0 { format!("epsilon = {}", f.xsph) } else { "off".into() }
    );
    let l = &p.limits;
    let _ = writeln!(
        s,
        "fluid dt     {:.6e} s, set by {}: CFL 0.25 h/(c0 + v) = {:.4e} s, viscous 0.125 h² rho0/mu = {:.4e} s, force 0.25 sqrt(h/|g|) = {:.4e} s",
        l.dt(),
        l.binding(),
        l.cfl,
        l.viscous,
        l.force
    );
    for (k, w) in f.moving_walls.iter().enumerate() {
        let motion = match w.motion {
            tumble_geom::Motion::Rotate { point, axis, omega } => {
                format!("turns at {:.4} rpm about the axis through {point} along {axis}", omega * 60.0 / std::f64::consts::TAU)
            }
            tumble_geom::Motion::Translate { velocity } => format!("translates at {velocity} m/s"),
            tumble_geom::Motion::Oscillate { direction, amplitude, omega } => {
                format!("oscillates along {direction}, amplitude {amplitude} m at {:.4} Hz", omega / std::f64::consts::TAU)
            }
        };
        let stop = if w.timing.stop.is_finite() { format!(", stops at {} s", w.timing.stop) } else { String::new() };
        let _ = writeln!(
            s,
            "fluid wall   moving wall {}: {motion} from {} s (ramp {} s{stop}); its wall particles follow, Adami's condition with their acceleration",
            k + 1,
            w.timing.start,
            w.timing.ramp
        );
    }
    for (name, body) in p.floating.iter().zip(&f.floating) {
        let _ = writeln!(
            s,
            "fluid body   \"{name}\": {:.4e} kg{}, centre {} m, moved by the fluid's pressure and viscosity and by gravity (it does not collide with walls or other bodies); floating_{name}.csv",
            body.mass,
            if f.dimension == Dimension::Two { " per metre of span" } else { "" },
            body.start.centre
        );
    }
    for (k, inflow) in f.inflows.iter().enumerate() {
        let b = &inflow.buffer;
        let _ = writeln!(
            s,
            "fluid inflow {k}: box {} to {} m, fluid enters at {} m/s{}{} through its face at {} = {} m; its particles take the fluid's pressure continued across that face",
            b.region.min,
            b.region.max,
            inflow.velocity(),
            match inflow.profile {
                tumble_sph::InflowProfile::Uniform => "",
                tumble_sph::InflowProfile::Parabolic => " on average, in a parabolic profile",
            },
            if inflow.timing.ramp > 0.0 { format!(", ramped up over {} s", inflow.timing.ramp) } else { String::new() },
            ["x", "y", "z"][b.axis],
            if b.sign > 0.0 { b.region.max[b.axis] } else { b.region.min[b.axis] }
        );
    }
    for (k, outflow) in f.outflows.iter().enumerate() {
        let b = &outflow.buffer;
        let _ = writeln!(
            s,
            "fluid outflow {k}: box {} to {} m, fluid leaves along {} at {} Pa; fluid.csv counts mass_in, mass_out",
            b.region.min,
            b.region.max,
            b.direction(),
            outflow.pressure
        );
    }
    for probe in &p.probes {
        let what = match probe.kind {
            crate::SphProbeKind::Pressure(x) => format!("pressure at {x}"),
            crate::SphProbeKind::Velocity(x) => format!("velocity at {x}"),
            crate::SphProbeKind::Gauge { from, top } => format!("water height from {from} up to z = {top}"),
            crate::SphProbeKind::Front(d) => format!("front along {d}"),
        };
        let _ = writeln!(s, "fluid probe  {}: {what} (probe_{}.csv)", probe.name, probe.name);
    }
}
