//! A small seeded generator (SplitMix64) so scenes are reproducible without a dependency.

pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    /// The generator's state, to continue its sequence later ([`Rng::from_state`]).
    pub fn state(&self) -> u64 {
        self.0
    }

    /// A generator continuing from [`Rng::state`].
    pub fn from_state(state: u64) -> Self {
        Rng(state)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// A uniformly distributed unit vector.
    pub fn direction(&mut self) -> glam::DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        glam::DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }

    /// A rotation uniformly distributed over SO(3) (Shoemake's subgroup algorithm).
    pub fn rotation(&mut self) -> glam::DQuat {
        let (u1, u2, u3) = (self.uniform(), self.range(0.0, std::f64::consts::TAU), self.range(0.0, std::f64::consts::TAU));
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        glam::DQuat::from_xyzw(a * u2.sin(), a * u2.cos(), b * u3.sin(), b * u3.cos()).normalize()
    }
}
