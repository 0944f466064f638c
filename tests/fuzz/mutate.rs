//! Structural mutations of a scene's `toml::Value`: extreme numbers, wrong types, missing,
//! duplicated and grafted sections, strange strings. Each returns one line saying what it did.

use super::{Rng, Seed};
use toml::Value;
use toml::value::{Array, Table};

#[derive(Clone, Debug, PartialEq)]
enum Part {
    Key(String),
    Index(usize),
}

type NodePath = Vec<Part>;

fn show(path: &[Part]) -> String {
    let mut s = String::new();
    for part in path {
        match part {
            Part::Key(k) if s.is_empty() => s.push_str(k),
            Part::Key(k) => s.push_str(&format!(".{k}")),
            Part::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// Every node below `value` (not `value` itself), parents before children.
fn paths(value: &Value) -> Vec<NodePath> {
    fn walk(v: &Value, here: &mut NodePath, out: &mut Vec<NodePath>) {
        match v {
            Value::Table(t) => {
                for (k, child) in t {
                    here.push(Part::Key(k.clone()));
                    out.push(here.clone());
                    walk(child, here, out);
                    here.pop();
                }
            }
            Value::Array(a) => {
                for (i, child) in a.iter().enumerate() {
                    here.push(Part::Index(i));
                    out.push(here.clone());
                    walk(child, here, out);
                    here.pop();
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(value, &mut Vec::new(), &mut out);
    out
}

fn get_mut<'a>(value: &'a mut Value, path: &[Part]) -> Option<&'a mut Value> {
    let mut v = value;
    for part in path {
        v = match (part, v) {
            (Part::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Part::Index(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

fn get<'a>(value: &'a Value, path: &[Part]) -> Option<&'a Value> {
    let mut v = value;
    for part in path {
        v = match (part, v) {
            (Part::Key(k), Value::Table(t)) => t.get(k)?,
            (Part::Index(i), Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

fn remove(value: &mut Value, path: &[Part]) {
    let Some((last, parent)) = path.split_last() else { return };
    match (last, get_mut(value, parent)) {
        (Part::Key(k), Some(Value::Table(t))) => {
            t.remove(k);
        }
        (Part::Index(i), Some(Value::Array(a))) if *i < a.len() => {
            a.remove(*i);
        }
        _ => {}
    }
}

/// Floats a number may become: the edges of f64 and of physical sense.
fn extreme_float(x: f64, rng: &mut Rng) -> f64 {
    let choices = [
        0.0,
        -0.0,
        -x,
        -1.0,
        1.0,
        1e308,
        -1e308,
        f64::MAX,
        1e-320,
        f64::MIN_POSITIVE,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e-300,
        1e300,
        x * 1e-9,
        x * 1e9,
    ];
    *rng.pick(&choices)
}

/// Integers a count may become: zero, negative, the edges of u16, u32 and i64, huge.
fn extreme_int(n: i64, rng: &mut Rng) -> Value {
    let ints = [
        0,
        -1,
        1,
        n.wrapping_neg(),
        i64::MAX,
        i64::MIN,
        u32::MAX as i64,
        u32::MAX as i64 + 1,
        u16::MAX as i64,
        u16::MAX as i64 + 1,
        1 << 31,
        1_000_000,
        1_000_000_000,
        1_000_000_000_000,
        n.saturating_mul(1000),
    ];
    match rng.below(5) {
        0 => Value::Float(extreme_float(n as f64, rng)),
        _ => Value::Integer(*rng.pick(&ints)),
    }
}

fn weird_string(rng: &mut Rng) -> String {
    match rng.below(9) {
        0 => String::new(),
        1 => " ".into(),
        2 => "y".repeat(10_000),
        3 => "a\nb\r\n\u{0}c".into(),
        4 => "\u{202e}ünïcødé 🎲".into(),
        5 => "x".repeat(61),
        6 => "\"quoted\" and \\ back".into(),
        7 => "[x]".into(),
        _ => "1.0".into(),
    }
}

/// A value of another type than `v`.
fn other_type(v: &Value, corpus: &[Seed], rng: &mut Rng) -> Value {
    loop {
        let candidate = match rng.below(8) {
            0 => Value::String(weird_string(rng)),
            1 => Value::Integer(7),
            2 => Value::Float(0.5),
            3 => Value::Boolean(true),
            4 => Value::Array(Array::new()),
            5 => Value::Array(vec![Value::Float(1.0), Value::String("a".into()), Value::Array(vec![])]),
            6 => Value::Table(Table::new()),
            _ => corpus_leaf(corpus, rng).unwrap_or(Value::Boolean(false)),
        };
        if candidate.type_str() != v.type_str() {
            return candidate;
        }
    }
}

/// Some scene's value: a node of a corpus scene, at random.
fn corpus_node(corpus: &[Seed], rng: &mut Rng) -> Option<(NodePath, Value)> {
    let value = corpus[rng.below(corpus.len())].value.as_ref()?;
    let all = paths(value);
    if all.is_empty() {
        return None;
    }
    let path = rng.pick(&all).clone();
    let node = get(value, &path)?.clone();
    Some((path, node))
}

fn corpus_leaf(corpus: &[Seed], rng: &mut Rng) -> Option<Value> {
    for _ in 0..8 {
        if let Some((_, v)) = corpus_node(corpus, rng)
            && !matches!(v, Value::Table(_) | Value::Array(_))
        {
            return Some(v);
        }
    }
    None
}

fn corpus_string(corpus: &[Seed], rng: &mut Rng) -> Option<String> {
    for _ in 0..16 {
        if let Some(Value::String(s)) = corpus_leaf(corpus, rng) {
            return Some(s);
        }
    }
    None
}

/// Applies one mutation to `value` and says which.
/// A `mild` one only changes a number or a string, or grafts another scene's value.
pub fn mutate(value: &mut Value, corpus: &[Seed], rng: &mut Rng, mild: bool) -> String {
    let all = paths(value);
    if all.is_empty() {
        return "(empty scene, not mutated)".into();
    }
    let numbers: Vec<&NodePath> = all.iter().filter(|p| matches!(get(value, p), Some(Value::Integer(_) | Value::Float(_)))).collect();
    let strings: Vec<&NodePath> = all.iter().filter(|p| matches!(get(value, p), Some(Value::String(_)))).collect();
    let arrays: Vec<&NodePath> = all.iter().filter(|p| matches!(get(value, p), Some(Value::Array(a)) if !a.is_empty())).collect();
    let tables: Vec<NodePath> =
        std::iter::once(Vec::new()).chain(all.iter().filter(|p| matches!(get(value, p), Some(Value::Table(_)))).cloned()).collect();
    let roll = if mild { *rng.pick(&[0, 30, 35, 70, 75, 85]) } else { rng.below(100) };
    match roll {
        0..30 if !numbers.is_empty() => {
            let path = (*rng.pick(&numbers)).clone();
            let node = get_mut(value, &path).unwrap();
            *node = match node {
                Value::Integer(n) => extreme_int(*n, rng),
                Value::Float(x) => Value::Float(extreme_float(*x, rng)),
                _ => unreachable!(),
            };
            format!("{} = {}", show(&path), node)
        }
        30..40 if !numbers.is_empty() => {
            // A wrong unit: millimetres for metres, grams for kilograms.
            let path = (*rng.pick(&numbers)).clone();
            let k = rng.below(25) as i32 - 12;
            let node = get_mut(value, &path).unwrap();
            *node = match node {
                Value::Integer(n) if k >= 0 => Value::Integer(n.saturating_mul(10i64.saturating_pow(k as u32))),
                Value::Integer(n) => Value::Float(*n as f64 * 10f64.powi(k)),
                Value::Float(x) => Value::Float(*x * 10f64.powi(k)),
                _ => unreachable!(),
            };
            format!("{} scaled by 1e{k}: {}", show(&path), node)
        }
        40..50 => {
            let path = rng.pick(&all).clone();
            let node = get_mut(value, &path).unwrap();
            *node = other_type(node, corpus, rng);
            format!("{} retyped to {}", show(&path), node.type_str())
        }
        50..60 => {
            let path = rng.pick(&all).clone();
            remove(value, &path);
            format!("{} removed", show(&path))
        }
        60..68 if !arrays.is_empty() => {
            // Two identical particle groups, walls or materials; a repeated coordinate.
            let path = (*rng.pick(&arrays)).clone();
            let Some(Value::Array(a)) = get_mut(value, &path) else { unreachable!() };
            let k = rng.below(a.len());
            let copy = a[k].clone();
            if rng.chance(0.2) {
                a.clear()
            } else {
                a.insert(k, copy)
            }
            format!("{}[{k}] duplicated or the array emptied", show(&path))
        }
        68..82 => {
            // Another scene's section or value where this scene has (or lacks) one.
            let Some((path, node)) = corpus_node(corpus, rng) else { return "(no graft)".into() };
            let (last, parent) = path.split_last().unwrap();
            match (last, get_mut(value, parent)) {
                (Part::Key(k), Some(Value::Table(t))) => {
                    t.insert(k.clone(), node);
                }
                (Part::Index(i), Some(Value::Array(a))) => {
                    let at = (*i).min(a.len());
                    a.insert(at, node);
                }
                _ => return format!("(graft of {} found no parent)", show(&path)),
            }
            format!("{} grafted from another scene", show(&path))
        }
        82..92 if !strings.is_empty() => {
            let path = (*rng.pick(&strings)).clone();
            let s = if rng.chance(0.6) { corpus_string(corpus, rng).unwrap_or_default() } else { weird_string(rng) };
            let shown: String = s.chars().take(30).collect();
            *get_mut(value, &path).unwrap() = Value::String(s);
            format!("{} = {shown:?}", show(&path))
        }
        _ => {
            // A key from elsewhere (or nowhere) in a table.
            let path = rng.pick(&tables).clone();
            let key = match corpus_node(corpus, rng) {
                Some((p, _)) if rng.chance(0.8) => match p.last() {
                    Some(Part::Key(k)) => k.clone(),
                    _ => "bogus".into(),
                },
                _ => "bogus".into(),
            };
            let leaf = corpus_leaf(corpus, rng).unwrap_or(Value::Integer(1));
            let Some(Value::Table(t)) = get_mut(value, &path) else { unreachable!() };
            t.insert(key.clone(), leaf);
            format!("{}.{key} added", show(&path))
        }
    }
}
