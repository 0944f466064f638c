//! Byte corruptions of a scene's text: flipped, inserted and deleted bytes, truncation, and
//! lines or whole tables repeated, dropped or borrowed from another scene.

use super::{Rng, Seed};

/// Bytes and snippets that TOML gives meaning to, and some it forbids.
const SNIPPETS: [&[u8]; 22] = [
    b"[",
    b"]",
    b"[[",
    b"=",
    b"\"",
    b"'''",
    b"\n",
    b"#",
    b"{",
    b"}",
    b",",
    b".",
    b"\\",
    b"\\u{110000}",
    b"\x00",
    b"\xff\xfe",
    b"\xc3",
    b"\r",
    b"99999999999999999999999",
    b"1e999",
    b"nan",
    b"-inf",
];

fn lines(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' {
            out.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < bytes.len() {
        out.push((start, bytes.len()));
    }
    out
}

/// Applies one corruption to `bytes` and says which.
pub fn corrupt(bytes: &mut Vec<u8>, corpus: &[Seed], rng: &mut Rng) -> String {
    if bytes.is_empty() {
        bytes.extend_from_slice(SNIPPETS[rng.below(SNIPPETS.len())]);
        return "empty text: a snippet inserted".into();
    }
    let at = rng.below(bytes.len());
    match rng.below(11) {
        0 => {
            let bit = rng.below(8);
            bytes[at] ^= 1 << bit;
            format!("bit {bit} of byte {at} flipped")
        }
        1 => {
            let b = rng.next() as u8;
            bytes[at] = b;
            format!("byte {at} set to {b:#04x}")
        }
        2 | 3 => {
            let s = SNIPPETS[rng.below(SNIPPETS.len())];
            bytes.splice(at..at, s.iter().copied());
            format!("{:?} inserted at byte {at}", String::from_utf8_lossy(s))
        }
        4 => {
            let n = 1 + rng.below(16).min(bytes.len() - at - 1);
            bytes.drain(at..at + n);
            format!("{n} bytes deleted at byte {at}")
        }
        5 => {
            bytes.truncate(at);
            format!("truncated to {at} bytes")
        }
        6 | 7 => {
            // A line twice (a duplicated key or table header), or dropped.
            let ls = lines(bytes);
            let (s, e) = *rng.pick(&ls);
            let line = bytes[s..e].to_vec();
            if rng.chance(0.6) {
                bytes.splice(e..e, line.iter().copied());
                format!("line at byte {s} duplicated")
            } else {
                bytes.drain(s..e);
                format!("line at byte {s} deleted")
            }
        }
        8 => {
            // A whole table (its header to the next header) repeated.
            let ls = lines(bytes);
            let headers: Vec<usize> = (0..ls.len()).filter(|&k| bytes[ls[k].0..ls[k].1].trim_ascii_start().starts_with(b"[")).collect();
            let Some(&k) = (!headers.is_empty()).then(|| rng.pick(&headers)) else { return "(no table to repeat)".into() };
            let end = headers.iter().find(|&&h| h > k).map_or(bytes.len(), |&h| ls[h].0);
            let mut table = bytes[ls[k].0..end].to_vec();
            if !table.ends_with(b"\n") {
                table.push(b'\n');
            }
            bytes.extend_from_slice(&table);
            format!("table at byte {} repeated at the end", ls[k].0)
        }
        9 => {
            // A line of another scene.
            let other = &corpus[rng.below(corpus.len())];
            let ls = lines(other.text.as_bytes());
            if ls.is_empty() {
                return "(other scene empty)".into();
            }
            let (s, e) = *rng.pick(&ls);
            let line = other.text.as_bytes()[s..e].to_vec();
            let ours = lines(bytes);
            let (_, after) = *rng.pick(&ours);
            bytes.splice(after..after, line.iter().copied());
            format!("line of {} inserted at byte {after}", other.path.file_name().unwrap().to_string_lossy())
        }
        _ => {
            // Two lines swapped (a key moves into another table).
            let ls = lines(bytes);
            let (a, b) = (*rng.pick(&ls), *rng.pick(&ls));
            let (first, second) = if a.0 <= b.0 { (a, b) } else { (b, a) };
            if first == second {
                return "(same line twice, not swapped)".into();
            }
            let mut out = bytes[..first.0].to_vec();
            out.extend_from_slice(&bytes[second.0..second.1]);
            out.extend_from_slice(&bytes[first.1..second.0]);
            out.extend_from_slice(&bytes[first.0..first.1]);
            out.extend_from_slice(&bytes[second.1..]);
            *bytes = out;
            format!("lines at bytes {} and {} swapped", first.0, second.0)
        }
    }
}
