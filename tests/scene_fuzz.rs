//! The scene-file parser against a few thousand mutated example files (a seeded mutator, so
//! every run checks the same files): it never panics, every rejection names a line or a field,
//! and every scene it accepts is within the plausible ranges.

use mass_spring_solvers::particles::scene_file::{parse, LIMITS};
use std::path::Path;

/// Mutated files per example scene.
const CASES_PER_EXAMPLE: usize = 1200;

/// Values a hostile file puts where a number was.
const HOSTILE: [&str; 22] = [
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "-inf",
    "1e-320",
    "0",
    "-0.0",
    "9223372036854775807",
    "18446744073709551616",
    "-1",
    "1e9",
    "1e-9",
    "1e13",
    "\"junk\"",
    "[]",
    "[1, 2]",
    "[1, 2, 3, 4]",
    "true",
    "{}",
    "0x10",
    "1_000",
];

/// Characters a mutation inserts.
const NOISE: [char; 16] = [
    '[', ']', '{', '}', '=', ',', '.', '"', '#', '\n', '-', 'e', '9', ' ', 'ñ', '\u{0}',
];

/// xorshift64*: a small seeded generator, so the mutated files are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Byte ranges of the numbers in `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        if starts && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric()) {
            let start = i;
            i += 1;
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric() || b".-+".contains(&bytes[i]))
            {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut text = text.to_string();
    for _ in 0..1 + rng.below(3) {
        let lines: Vec<&str> = text.lines().collect();
        let line = rng.below(lines.len());
        text = match rng.below(7) {
            0 | 1 => {
                let spots = numbers(&text);
                if spots.is_empty() {
                    continue;
                }
                let (a, b) = spots[rng.below(spots.len())];
                format!(
                    "{}{}{}",
                    &text[..a],
                    HOSTILE[rng.below(HOSTILE.len())],
                    &text[b..]
                )
            }
            2 if !lines.is_empty() => {
                let mut l = lines.clone();
                l.remove(line);
                l.join("\n")
            }
            3 if !lines.is_empty() => {
                let mut l = lines.clone();
                l.insert(line, lines[line]);
                l.join("\n")
            }
            4 => {
                let mut chars: Vec<char> = text.chars().collect();
                let at = rng.below(chars.len() + 1);
                chars.insert(at, NOISE[rng.below(NOISE.len())]);
                chars.into_iter().collect()
            }
            5 => text
                .chars()
                .take(rng.below(text.chars().count() + 1))
                .collect(),
            6 if !lines.is_empty() => {
                let mut l = lines.clone();
                l.swap(line, rng.below(lines.len()));
                l.join("\n")
            }
            _ => continue,
        };
    }
    text
}

fn accepted_scene_is_plausible(text: &str) {
    let scene = parse(text).unwrap();
    let s = &scene.system;
    let g = s.gravity();
    assert!(g.iter().all(|x| x.abs() <= LIMITS.gravity.max), "{text}");
    for n in s.nodes() {
        assert!(
            (LIMITS.mass.min..=LIMITS.mass.max).contains(&n.mass),
            "{text}"
        );
        assert!(
            n.position.iter().all(|x| x.abs() <= LIMITS.coordinate.max),
            "{text}"
        );
        assert!(
            n.velocity.iter().all(|x| x.abs() <= LIMITS.velocity.max),
            "{text}"
        );
    }
    for sp in s.springs() {
        assert!(
            sp.stiffness.is_finite() && sp.stiffness <= LIMITS.stiffness.max,
            "{text}"
        );
        assert!(sp.rest_length.is_finite() && sp.rest_length > 0.0, "{text}");
        assert!(sp.a < s.len() && sp.b < s.len(), "{text}");
    }
}

#[test]
fn mutated_scene_files_never_panic_and_every_rejection_names_a_line_or_a_field() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (mut accepted, mut rejected) = (0, 0);
    for (k, example) in ["thesis-rope.toml", "pendulum.toml", "hanging-cloth.toml"]
        .into_iter()
        .enumerate()
    {
        let original = std::fs::read_to_string(root.join("scenes").join(example)).unwrap();
        parse(&original).expect("the example itself is good");
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ (k as u64 + 1));
        for case in 0..CASES_PER_EXAMPLE {
            let text = mutate(&original, &mut rng);
            let outcome = std::panic::catch_unwind(|| parse(&text))
                .unwrap_or_else(|_| panic!("{example}, case {case}: parse panicked on\n{text}"));
            match outcome {
                Ok(_) => {
                    accepted += 1;
                    accepted_scene_is_plausible(&text);
                }
                Err(e) => {
                    rejected += 1;
                    let message = e.to_string();
                    assert!(
                        message.contains("line ") || message.starts_with("invalid "),
                        "{example}, case {case}: {message}\n{text}"
                    );
                }
            }
        }
    }
    // The mutator must exercise both sides, or the test checks little.
    assert!(
        accepted > 100 && rejected > 1000,
        "{accepted} accepted, {rejected} rejected"
    );
}
