//! The scene fuzzer's generator: a seeded RNG and a case built from one corpus scene by
//! structural mutations of its `toml::Value` and byte corruptions of its text.
#![allow(dead_code)]

mod corrupt;
mod mutate;

use std::path::{Path, PathBuf};
use toml::Value;

/// SplitMix64 (Steele, Lea & Flood 2014): tiny, seedable and the same on every platform, so a
/// (seed, case) pair names one scene for ever.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The stream of case `index` under `seed`: independent of every other case, so cases can
    /// run in any order on any number of threads.
    pub fn for_case(seed: u64, index: u64) -> Rng {
        let mut r = Rng(seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        r.next();
        r
    }

    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        ((self.next() >> 11) as f64 / (1u64 << 53) as f64) < p
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// One shipped or bad scene: its file, text and (where it parses as TOML) its value.
pub struct Seed {
    pub path: PathBuf,
    pub text: String,
    pub value: Option<Value>,
    /// A shipped scene (not one of tests/bad_scenes/).
    pub runs: bool,
}

/// The scenes the cases start from: `scenes/*.toml`, `scenes/test/*.toml` and
/// `tests/bad_scenes/*.toml`, in name order.
pub fn corpus(root: &Path) -> Vec<Seed> {
    let mut paths = Vec::new();
    for dir in ["scenes", "scenes/test", "tests/bad_scenes"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                paths.push(path);
            }
        }
    }
    paths.sort();
    paths
        .into_iter()
        .map(|path| {
            let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
            let value = toml::from_str::<Value>(&text).ok();
            let runs = !path.starts_with(root.join("tests"));
            Seed { path, text, value, runs }
        })
        .collect()
}

/// How a case was made, for the failure report.
#[derive(Clone, Debug)]
pub struct Case {
    pub index: u64,
    pub base: PathBuf,
    /// The mutations applied, in order (`run.dt = nan`, `flip byte 311`).
    pub steps: Vec<String>,
    pub bytes: Vec<u8>,
}

/// Case `index` under `seed`: a corpus scene with one mild change, or a few structural
/// mutations, byte corruptions, or both.
pub fn case(corpus: &[Seed], seed: u64, index: u64) -> Case {
    let mut rng = Rng::for_case(seed, index);
    let mut steps = Vec::new();
    let roll = rng.below(100);
    // A third of the cases change one thing in a scene that runs, so many get through the
    // compiler to the steps; the rest pile up mutations and corruptions on any scene.
    let mild = roll < 35;
    let base = if mild {
        let good: Vec<&Seed> = corpus.iter().filter(|s| s.runs && s.value.is_some()).collect();
        good[rng.below(good.len())]
    } else {
        &corpus[rng.below(corpus.len())]
    };
    let structural = base.value.is_some() && roll < 85;
    let mut text = match (&base.value, structural) {
        (Some(value), true) => {
            let mut value = value.clone();
            let count = if mild { 1 } else { 1 + rng.below(3) };
            for _ in 0..count {
                steps.push(mutate::mutate(&mut value, corpus, &mut rng, mild));
            }
            toml::to_string(&value).unwrap_or_else(|e| {
                steps.push(format!("(not serialisable: {e}; the base text instead)"));
                base.text.clone()
            })
        }
        _ => base.text.clone(),
    };
    let mut bytes = std::mem::take(&mut text).into_bytes();
    // Structural cases are corrupted a quarter of the time; text-only ones always.
    if !structural || (!mild && rng.chance(0.25)) {
        let count = 1 + rng.below(3);
        for _ in 0..count {
            steps.push(corrupt::corrupt(&mut bytes, corpus, &mut rng));
        }
    }
    Case { index, base: base.path.clone(), steps, bytes }
}
