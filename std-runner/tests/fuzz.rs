//! A standing, seeded mutation test of everything `strata` reads back:
//! checkpoints (`render --resume`), partial films (`merge`) and scene files
//! (`render --scene`). Each case damages a valid input (bit flips, byte
//! changes, cuts, padding, header values swapped for extreme numbers or
//! words, pixel counts changed and the checksums recomputed, records
//! spliced in from another seed's render, extra vector components), runs
//! the command as a process under a memory and CPU limit, and sorts the
//! outcome:
//!
//! - *refused*: a clear error (exit 1), only the inputs left;
//! - *equal*: accepted, and the output is byte for byte the one-shot
//!   render's (damage that only cost a re-render, e.g. a torn record);
//! - *accepted*: a scene file still valid after the change, rendered;
//! - *wrong*: accepted, but the output differs or is elsewhere;
//! - *panic*, *crash* (killed by a signal: an allocation over the limit
//!   aborts), *hang* (no exit within [`HANG_SECONDS`]), *leftovers*
//!   (files beyond the inputs and the output).
//!
//! The suite runs [`SUITE_CASES`] cases of each kind and asserts that none
//! is wrong, a panic, a crash, a hang or leaves files. The same harness
//! reports counts for any binary and case count:
//! `STRATA_FUZZ_BIN=path STRATA_FUZZ_CASES=300 cargo test --release -p
//! strata-runner --test fuzz -- --ignored --nocapture`.
//!
//! The one time-bound is the hang limit, a safety net hundreds of times
//! the few milliseconds a case takes; every other verdict is by exit
//! status and bytes.

use std::collections::BTreeMap;
use std::io::Read;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Cases of each kind in the suite's run.
const SUITE_CASES: usize = 200;

/// A case still running after this long is a hang.
const HANG_SECONDS: u64 = 120;

/// The address-space limit of each case, in KiB (2 GiB): a damaged
/// header that asks for more is a crash, not a machine brought down.
const MEMORY_KIB: u64 = 2 << 20;

fn binary() -> PathBuf {
    std::env::var_os("STRATA_FUZZ_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_strata")))
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

use strata_runner::hash::fnv1a;

/// How one case ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Verdict {
    Refused,
    Equal,
    Accepted,
    Wrong,
    Panic,
    Crash,
    Hang,
    Leftovers,
}

const BAD: [Verdict; 5] = [
    Verdict::Wrong,
    Verdict::Panic,
    Verdict::Crash,
    Verdict::Hang,
    Verdict::Leftovers,
];

struct Run {
    code: Option<i32>,
    signal: Option<i32>,
    stderr: String,
    hung: bool,
}

/// Runs `strata args` in `dir` under the memory and CPU limits.
fn run(dir: &Path, args: &[String]) -> Run {
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg(format!(
            "ulimit -v {MEMORY_KIB}; ulimit -t {HANG_SECONDS}; exec \"$0\" \"$@\""
        ))
        .arg(binary())
        .args(args)
        .current_dir(dir)
        .env_remove("STRATA_TEST_HOOK")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let mut child = c.spawn().expect("sh runs");
    let mut err = child.stderr.take().expect("piped");
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        err.read_to_end(&mut s).ok();
        String::from_utf8_lossy(&s).into_owned()
    });
    let start = Instant::now();
    let (status, hung) = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break (s, false);
        }
        if start.elapsed() > Duration::from_secs(HANG_SECONDS) {
            child.kill().ok();
            break (child.wait().expect("wait"), true);
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Run {
        code: status.code(),
        signal: status.signal(),
        stderr: reader.join().unwrap_or_default(),
        hung,
    }
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn clear(dir: &Path) {
    for n in names(dir) {
        let p = dir.join(n);
        if p.is_dir() {
            std::fs::remove_dir_all(p).ok();
        } else {
            std::fs::remove_file(p).ok();
        }
    }
}

/// Sorts a finished run. `inputs`: the files the case wrote; `output`:
/// the file an accepted run writes and `want` its one-shot bytes (`None`:
/// any image will do, as for a changed but valid scene file).
fn verdict(
    run: &Run,
    dir: &Path,
    inputs: &[&str],
    output: &str,
    want: Option<&[u8]>,
    consumed: bool,
) -> Verdict {
    if run.hung {
        return Verdict::Hang;
    }
    if run.code == Some(101) || run.stderr.contains("panicked") {
        return Verdict::Panic;
    }
    if run.signal.is_some() {
        return Verdict::Crash;
    }
    let listed = names(dir);
    if run.code == Some(0) {
        let mut expect: Vec<String> = inputs
            .iter()
            .filter(|_| !consumed)
            .map(|s| s.to_string())
            .collect();
        expect.push(output.to_string());
        expect.sort();
        let got = std::fs::read(dir.join(output)).ok();
        let right = match (want, &got) {
            (_, None) => false,
            (None, Some(_)) => true,
            (Some(w), Some(g)) => w == g.as_slice(),
        };
        if !right {
            return Verdict::Wrong;
        }
        if listed != expect {
            return Verdict::Leftovers;
        }
        return if want.is_some() {
            Verdict::Equal
        } else {
            Verdict::Accepted
        };
    }
    let mut expect: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    expect.sort();
    if listed != expect {
        return Verdict::Leftovers;
    }
    Verdict::Refused
}

/// Where the text header of a film or checkpoint ends (after its empty
/// line).
fn header_end(b: &[u8]) -> Option<usize> {
    b.windows(2).position(|w| w == b"\n\n").map(|p| p + 2)
}

/// Recomputes a film's checksums after an edit: the body's, then (in
/// formats that have one) the header's own.
fn reseal_film(b: &mut Vec<u8>) {
    let Some(end) = header_end(b) else { return };
    let head = String::from_utf8_lossy(&b[..end - 1]).into_owned();
    let body = b[end..].to_vec();
    let mut out = String::new();
    for line in head.lines() {
        if line.starts_with("checksum=") {
            out.push_str(&format!("checksum={:016x}\n", fnv1a(&body)));
        } else if line.starts_with("head_checksum=") {
            let sum = fnv1a(out.as_bytes());
            out.push_str(&format!("head_checksum={sum:016x}\n"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    out.push('\n');
    let mut v = out.into_bytes();
    v.extend_from_slice(&body);
    *b = v;
}

/// The record layout of a checkpoint: the header's end, the bytes before
/// a record's pixel count, and those around its pixels.
fn checkpoint_layout(b: &[u8]) -> Option<(usize, usize, usize)> {
    let end = header_end(b)?;
    if b.starts_with(b"strata-checkpoint 1\n") {
        // TILE, index, count | 3 counts | pixels | FNV.
        Some((end, 8, 44))
    } else {
        // TILE, render id, index, count | 3 counts | pixels | FNV.
        Some((end, 16, 52))
    }
}

/// The (start, length) of every whole record.
fn records(b: &[u8]) -> Vec<(usize, usize)> {
    let Some((mut at, count_at, overhead)) = checkpoint_layout(b) else {
        return vec![];
    };
    let mut out = vec![];
    while at + count_at + 4 <= b.len() {
        let n =
            u32::from_le_bytes(b[at + count_at..at + count_at + 4].try_into().unwrap()) as usize;
        let len = overhead + 64 * n;
        if at + len > b.len() {
            break;
        }
        out.push((at, len));
        at += len;
    }
    out
}

fn reseal_record(b: &mut [u8], (at, len): (usize, usize)) {
    let sum = fnv1a(&b[at..at + len - 8]);
    b[at + len - 8..at + len].copy_from_slice(&sum.to_le_bytes());
}

/// Recomputes a checkpoint's checksums after an edit of its header: the
/// header's own (in formats that have one), then each record's render id
/// and checksum, so that what lies behind the checksums is reached.
fn reseal_checkpoint(b: &mut Vec<u8>) {
    let Some(end) = header_end(b) else { return };
    let head = &b[..end - 2];
    let Some(last) = head.iter().rposition(|&c| c == b'\n').map(|i| i + 1) else {
        return;
    };
    if !head[last..].starts_with(b"head_checksum=") {
        return;
    }
    let id = fnv1a(&b[..last]);
    let mut out = b[..last].to_vec();
    out.extend_from_slice(format!("head_checksum={id:016x}\n\n").as_bytes());
    let body = b[end..].to_vec();
    out.extend_from_slice(&body);
    *b = out;
    for r in records(b) {
        b[r.0 + 4..r.0 + 12].copy_from_slice(&id.to_le_bytes());
        reseal_record(b, r);
    }
}

/// Numbers and words a damaged header value may hold.
const NUMBERS: [&str; 10] = [
    "0",
    "1",
    "90",
    "600",
    "65535",
    "4294967295",
    "18446744073709551615",
    "99999999999999999999",
    "-1",
    "1e30",
];
const WORDS: [&str; 4] = ["hello", "banana", "", "9.9.9+r99"];

/// Header keys whose values have a type (a number, a name from a list, a
/// hex digest or this build's version): no word of [`WORDS`] is one.
const TYPED_KEYS: [&str; 8] = [
    "version",
    "scene_hash",
    "sampler",
    "seed",
    "max_depth",
    "direct_lighting",
    "texture_filter",
    "filter",
];

/// Sets header line `key=` to `value`, if the header has it.
fn set_header_value(b: &mut Vec<u8>, key: &str, value: &str) {
    let Some(end) = header_end(b) else { return };
    let head = String::from_utf8_lossy(&b[..end - 1]).into_owned();
    let prefix = format!("{key}=");
    let mut out = String::new();
    for line in head.lines() {
        match line.starts_with(&prefix) {
            true => out.push_str(&format!("{prefix}{value}\n")),
            false => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    out.push('\n');
    let mut v = out.into_bytes();
    v.extend_from_slice(&b[end..]);
    *b = v;
}

/// Replaces one number (or with `word`, one whole value) in a random
/// header line.
fn edit_header_value(b: &mut Vec<u8>, rng: &mut Rng, word: bool) -> bool {
    let Some(end) = header_end(b) else {
        return false;
    };
    let head = String::from_utf8_lossy(&b[..end - 1]).into_owned();
    let lines: Vec<&str> = head.lines().collect();
    if lines.len() < 2 {
        return false;
    }
    // Half the edits go to a checkpoint's flags (one long line).
    let k = match lines.iter().position(|l| l.starts_with("args=")) {
        Some(a) if rng.below(2) == 0 => a,
        _ => 1 + rng.below(lines.len() - 1),
    };
    let line = lines[k];
    let new_line = if word {
        match line.split_once('=') {
            Some((key, _)) => format!("{key}={}", rng.pick(&WORDS)),
            None => return false,
        }
    } else {
        // The digit runs of the line; one is replaced.
        let runs: Vec<(usize, usize)> = {
            let bytes = line.as_bytes();
            let mut v = vec![];
            let mut i = 0;
            while i < bytes.len() {
                if bytes[i].is_ascii_digit() {
                    let s = i;
                    while i < bytes.len() && bytes[i].is_ascii_digit() {
                        i += 1;
                    }
                    v.push((s, i));
                } else {
                    i += 1;
                }
            }
            v
        };
        if runs.is_empty() {
            return false;
        }
        let (s, e) = *rng.pick(&runs);
        format!("{}{}{}", &line[..s], rng.pick(&NUMBERS), &line[e..])
    };
    let mut new_head: Vec<&str> = lines.clone();
    new_head[k] = &new_line;
    let mut v = new_head.join("\n").into_bytes();
    v.extend_from_slice(b"\n\n");
    v.extend_from_slice(&b[end..]);
    *b = v;
    true
}

/// Byte-level damage anywhere: a flipped bit, a changed byte, a cut,
/// padding, or a repeated slice.
fn damage_bytes(b: &mut Vec<u8>, rng: &mut Rng) -> &'static str {
    let n = b.len().max(1);
    // Half the flips fall in the header, which is small.
    let head = header_end(b).unwrap_or(n).min(n);
    let at = if rng.below(2) == 0 {
        rng.below(head)
    } else {
        rng.below(n)
    };
    match rng.below(5) {
        0 => {
            b[at] ^= 1 << rng.below(8);
            "bit flip"
        }
        1 => {
            b[at] = rng.next() as u8;
            "byte"
        }
        2 => {
            b.truncate(at);
            "cut"
        }
        3 => {
            let extra = 1 + rng.below(100);
            for _ in 0..extra {
                b.push(rng.next() as u8);
            }
            "padding"
        }
        _ => {
            let len = 1 + rng.below(64).min(n - at);
            let piece = b[at..(at + len).min(b.len())].to_vec();
            let to = rng.below(b.len());
            b.splice(to..to, piece);
            "repeat"
        }
    }
}

#[derive(Default)]
struct Tally {
    counts: BTreeMap<Verdict, usize>,
    examples: Vec<String>,
    /// Per mutation: cases, and those refused by a header checksum.
    by_kind: BTreeMap<String, (usize, usize)>,
}

/// Whether a refusal came from a header's checksum (not from what lies
/// behind it).
fn by_checksum(stderr: &str) -> bool {
    stderr.contains("header is damaged") || stderr.contains("header's checksum does not match")
}

impl Tally {
    fn add(&mut self, v: Verdict, what: &str, stderr: &str) {
        *self.counts.entry(v).or_default() += 1;
        let k = self.by_kind.entry(what.to_string()).or_default();
        k.0 += 1;
        k.1 += by_checksum(stderr) as usize;
        // A few of each bad kind, so a rare panic is shown beside many
        // wrong files.
        let shown = self
            .examples
            .iter()
            .filter(|e| e.starts_with(&format!("{v:?}:")))
            .count();
        if BAD.contains(&v) && shown < 3 {
            let err: String = stderr
                .lines()
                .last()
                .unwrap_or("")
                .chars()
                .take(160)
                .collect();
            self.examples.push(format!("{v:?}: {what}: {err}"));
        }
    }
    fn bad(&self) -> usize {
        BAD.iter()
            .map(|v| self.counts.get(v).copied().unwrap_or(0))
            .sum()
    }
    fn line(&self, kind: &str) -> String {
        let mut s = format!("{kind:<12}");
        for v in [
            Verdict::Refused,
            Verdict::Equal,
            Verdict::Accepted,
            Verdict::Wrong,
            Verdict::Panic,
            Verdict::Crash,
            Verdict::Hang,
            Verdict::Leftovers,
        ] {
            s.push_str(&format!(
                " {:?} {}",
                v,
                self.counts.get(&v).copied().unwrap_or(0)
            ));
        }
        s
    }
}

fn ok(dir: &Path, args: &[&str], hook: Option<&str>) {
    let mut c = Command::new(binary());
    c.args(args).current_dir(dir).env_remove("STRATA_TEST_HOOK");
    if let Some(h) = hook {
        c.env("STRATA_TEST_HOOK", h);
    }
    let out = c.output().expect("strata runs");
    assert!(
        hook.is_some() || out.status.success(),
        "strata {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn s(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

/// A render interrupted after `after` tiles: its checkpoint's bytes and
/// the one-shot output's.
struct CheckpointSeed {
    dir: PathBuf,
    output: &'static str,
    checkpoint: Vec<u8>,
    /// The same render with another seed, interrupted alike.
    other_seed: Vec<u8>,
    want: Vec<u8>,
}

fn checkpoint_seeds(root: &Path) -> Vec<CheckpointSeed> {
    let configs: [(&[&str], &str, usize); 3] = [
        (
            &[
                "--scene", "cover", "--width", "48", "--spp", "2", "--tile", "8",
            ],
            "c.png",
            5,
        ),
        (
            &[
                "--scene",
                "showcase",
                "--width",
                "48",
                "--spp",
                "2",
                "--tile",
                "8",
                "--filter",
                "mitchell",
                "--pixel-bounds",
                "4,40,2,20",
            ],
            "c.film",
            3,
        ),
        (
            &[
                "--scene",
                "week09",
                "--width",
                "32",
                "--adaptive",
                "--min-spp",
                "8",
                "--max-spp",
                "16",
                "--sampler",
                "sobol",
                "--tile",
                "8",
            ],
            "c.exr",
            4,
        ),
    ];
    let mut out = vec![];
    for (i, (args, output, after)) in configs.into_iter().enumerate() {
        let dir = root.join(format!("checkpoint-{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        let mut one = vec!["render"];
        one.extend(args);
        one.extend(["--no-checkpoint", "-o", output]);
        ok(&dir, &one, None);
        let want = std::fs::read(dir.join(output)).unwrap();
        clear(&dir);
        let ckpt = format!("{output}.checkpoint");
        let mut interrupted = vec!["render"];
        interrupted.extend(args);
        interrupted.extend(["-o", output]);
        let hook = format!("after:{after}");
        let mut other = interrupted.clone();
        other.extend(["--seed", "1"]);
        ok(&dir, &other, Some(&hook));
        let other_seed = std::fs::read(dir.join(&ckpt)).unwrap();
        clear(&dir);
        ok(&dir, &interrupted, Some(&hook));
        let checkpoint = std::fs::read(dir.join(&ckpt)).unwrap();
        clear(&dir);
        assert_eq!(records(&checkpoint).len(), after, "seed {i}");
        out.push(CheckpointSeed {
            dir,
            output,
            checkpoint,
            other_seed,
            want,
        });
    }
    out
}

/// One damaged checkpoint, resumed.
fn checkpoint_case(seed: &CheckpointSeed, rng: &mut Rng, tally: &mut Tally) -> bool {
    let mut b = seed.checkpoint.clone();
    let recs = records(&b);
    let what = match rng.below(8) {
        0 | 1 => damage_bytes(&mut b, rng),
        2 => {
            if !edit_header_value(&mut b, rng, false) {
                return false;
            }
            "header number"
        }
        3 => {
            if !edit_header_value(&mut b, rng, true) {
                return false;
            }
            "header word"
        }
        6 | 7 => {
            // Behind the header's checksum: every setting's one check.
            let word = rng.below(4) == 0;
            if !edit_header_value(&mut b, rng, word) {
                return false;
            }
            reseal_checkpoint(&mut b);
            "header value, resealed"
        }
        4 => {
            // A pixel's sample count changed and the record resealed.
            let r = *rng.pick(&recs);
            let (_, _, overhead) = checkpoint_layout(&b).unwrap();
            let pixels = (r.1 - overhead) / 64;
            let px = r.0 + overhead - 8 + 64 * rng.below(pixels);
            let count: u32 = *rng.pick(&[0, 1, 3, u32::MAX, 1 << 31]);
            b[px + 32..px + 36].copy_from_slice(&count.to_le_bytes());
            reseal_record(&mut b, r);
            "resealed count"
        }
        _ => {
            // A record of the other seed's render in place of this one's.
            let other = records(&seed.other_seed);
            let k = rng.below(recs.len().min(other.len()));
            let (a, la) = recs[k];
            let (o, lo) = other[k];
            b.splice(a..a + la, seed.other_seed[o..o + lo].iter().copied());
            "other seed's record"
        }
    };
    let dir = &seed.dir;
    clear(dir);
    let ckpt = format!("{}.checkpoint", seed.output);
    std::fs::write(dir.join(&ckpt), &b).unwrap();
    let r = run(dir, &s(&["render", "--resume", &ckpt]));
    let v = verdict(&r, dir, &[&ckpt], seed.output, Some(&seed.want), true);
    tally.add(v, what, &r.stderr);
    true
}

/// Parts of a split render, and the one-shot image.
struct FilmSeed {
    dir: PathBuf,
    parts: Vec<Vec<u8>>,
    want: Vec<u8>,
}

fn film_seeds(root: &Path) -> Vec<FilmSeed> {
    let base: [&[&str]; 4] = [
        &["--scene", "cover", "--width", "48", "--spp", "2"],
        &[
            "--scene", "showcase", "--width", "48", "--spp", "2", "--filter", "mitchell",
        ],
        &[
            "--scene",
            "week09",
            "--width",
            "32",
            "--adaptive",
            "--min-spp",
            "8",
            "--max-spp",
            "16",
            "--sampler",
            "sobol",
        ],
        &["--scene", "horizon", "--width", "32", "--spp", "4"],
    ];
    let splits: [[&[&str]; 2]; 4] = [
        [
            &["--pixel-bounds", "0,24,0,27"],
            &["--pixel-bounds", "24,48,0,27"],
        ],
        [
            &["--pixel-bounds", "0,48,0,10"],
            &["--pixel-bounds", "0,48,10,27"],
        ],
        [
            &["--pixel-bounds", "0,16,0,18"],
            &["--pixel-bounds", "16,32,0,18"],
        ],
        [&["--samples", "0..1"], &["--samples", "1..4"]],
    ];
    let mut out = vec![];
    for (i, (args, split)) in base.iter().zip(splits).enumerate() {
        let dir = root.join(format!("film-{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        let mut one = vec!["render"];
        one.extend(*args);
        one.extend(["--no-checkpoint", "-o", "one.png"]);
        ok(&dir, &one, None);
        let want = std::fs::read(dir.join("one.png")).unwrap();
        let mut parts = vec![];
        for (k, part) in split.iter().enumerate() {
            let name = format!("p{k}.film");
            let mut a = vec!["render"];
            a.extend(*args);
            a.extend(*part);
            a.extend(["--no-checkpoint", "-o", &name]);
            ok(&dir, &a, None);
            parts.push(std::fs::read(dir.join(&name)).unwrap());
        }
        clear(&dir);
        out.push(FilmSeed { dir, parts, want });
    }
    out
}

/// One damaged part, merged with the others.
fn film_case(seed: &FilmSeed, rng: &mut Rng, tally: &mut Tally) -> bool {
    let k = rng.below(seed.parts.len());
    let mut b = seed.parts[k].clone();
    let mut parts = seed.parts.clone();
    let what = match rng.below(7) {
        6 => {
            // Every part relabelled alike (so they agree with each other)
            // with a value no render of this build has, and resealed.
            let key = *rng.pick(&TYPED_KEYS);
            let word = *rng.pick(&WORDS);
            for p in &mut parts {
                set_header_value(p, key, word);
                reseal_film(p);
            }
            b = parts[k].clone();
            "every part relabelled, resealed"
        }
        0 | 1 => damage_bytes(&mut b, rng),
        2 => {
            if !edit_header_value(&mut b, rng, false) {
                return false;
            }
            reseal_film(&mut b);
            "header number, resealed"
        }
        3 => {
            if !edit_header_value(&mut b, rng, true) {
                return false;
            }
            reseal_film(&mut b);
            "header word, resealed"
        }
        4 => {
            let Some(end) = header_end(&b) else {
                return false;
            };
            let pixels = (b.len() - end) / 64;
            let px = end + 64 * rng.below(pixels);
            let count: u32 = *rng.pick(&[0, 1, 3, u32::MAX, 1 << 31]);
            b[px + 32..px + 36].copy_from_slice(&count.to_le_bytes());
            reseal_film(&mut b);
            "resealed count"
        }
        _ => {
            if !edit_header_value(&mut b, rng, false) {
                return false;
            }
            "header number"
        }
    };
    let dir = &seed.dir;
    clear(dir);
    let mut inputs = vec![];
    for (i, p) in parts.iter().enumerate() {
        let name = format!("p{i}.film");
        std::fs::write(dir.join(&name), if i == k { &b } else { p }).unwrap();
        inputs.push(name);
    }
    let mut args = vec!["merge".to_string()];
    args.extend(inputs.iter().cloned());
    args.extend(s(&["-o", "out.png"]));
    let r = run(dir, &args);
    let refs: Vec<&str> = inputs.iter().map(String::as_str).collect();
    let v = verdict(&r, dir, &refs, "out.png", Some(&seed.want), false);
    tally.add(v, what, &r.stderr);
    true
}

const SCENES: [&str; 2] = [
    include_str!("../../examples/scenes/materials.toml"),
    "[camera]\nlook_from = [0.0, 1.0, 2.0]\nlook_at = [0.0, 0.0, -1.0]\nvfov = 50.0\n\n\
     [render]\nwidth = 16\nspp = 1\n\n[materials.m]\nkind = \"lambertian\"\nalbedo = [0.5, 0.5, 0.5]\n\n\
     [materials.l]\nkind = \"light\"\nemit = [4.0, 4.0, 4.0]\n\n\
     [[spheres]]\ncenter = [0.0, 0.0, -1.0]\nradius = 0.5\nmaterial = \"m\"\n\n\
     [[spheres]]\ncenter = [0.0, 3.0, -1.0]\nradius = 0.5\nmaterial = \"l\"\n",
];

/// One damaged scene file, rendered small. A vector given a fourth
/// component must be refused; other changes may leave a valid scene.
fn scene_case(dir: &Path, rng: &mut Rng, tally: &mut Tally) -> bool {
    let text = *rng.pick(&SCENES);
    let mut b = text.as_bytes().to_vec();
    let mut must_refuse = false;
    let what = match rng.below(4) {
        0 | 1 => damage_bytes(&mut b, rng),
        2 => {
            // A number of the file replaced by an extreme one.
            let t = String::from_utf8_lossy(&b).into_owned();
            let nums: Vec<(usize, usize)> = t
                .match_indices(|c: char| c.is_ascii_digit())
                .map(|(i, _)| (i, i + 1))
                .collect();
            let (i, e) = *rng.pick(&nums);
            let new = format!("{}{}{}", &t[..i], rng.pick(&NUMBERS), &t[e..]);
            b = new.into_bytes();
            "number"
        }
        _ => {
            // A three-component vector given a fourth.
            let t = String::from_utf8_lossy(&b).into_owned();
            let vecs: Vec<usize> = t
                .match_indices(" = [")
                .filter(|(i, _)| {
                    let rest = &t[i + 4..];
                    let close = rest.find(']').unwrap_or(0);
                    rest[..close].matches(',').count() == 2 && !rest[..close].contains('"')
                })
                .map(|(i, _)| i + 4)
                .collect();
            let at = *rng.pick(&vecs);
            let close = at + t[at..].find(']').unwrap();
            let new = format!("{}, 1.0{}", &t[..close], &t[close..]);
            b = new.into_bytes();
            must_refuse = true;
            "fourth component"
        }
    };
    clear(dir);
    std::fs::write(dir.join("s.toml"), &b).unwrap();
    let r = run(
        dir,
        &s(&[
            "render",
            "--scene",
            "s.toml",
            "--width",
            "16",
            "--spp",
            "1",
            "--max-depth",
            "4",
            "--no-checkpoint",
            "-o",
            "out.png",
        ]),
    );
    let mut v = verdict(&r, dir, &["s.toml"], "out.png", None, false);
    if must_refuse && v == Verdict::Accepted {
        v = Verdict::Wrong;
    }
    tally.add(v, what, &r.stderr);
    true
}

/// Runs `cases` cases of each kind from one fixed seed; the tallies of
/// checkpoints, films and scenes.
fn fuzz(cases: usize) -> [Tally; 3] {
    let root = tempfile::tempdir().unwrap();
    let mut rng = Rng(0x5eed_f022);
    let mut tallies = [Tally::default(), Tally::default(), Tally::default()];
    let ck = checkpoint_seeds(root.path());
    // A case whose mutation finds nothing to change (a header line
    // without digits) is drawn again.
    let mut ran = 0;
    while ran < cases {
        let seed = &ck[rng.below(ck.len())];
        ran += checkpoint_case(seed, &mut rng, &mut tallies[0]) as usize;
    }
    let films = film_seeds(root.path());
    let mut ran = 0;
    while ran < cases {
        let seed = &films[rng.below(films.len())];
        ran += film_case(seed, &mut rng, &mut tallies[1]) as usize;
    }
    let scenes = root.path().join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let mut ran = 0;
    while ran < cases {
        ran += scene_case(&scenes, &mut rng, &mut tallies[2]) as usize;
    }
    tallies
}

fn report(tallies: &[Tally; 3]) -> String {
    let mut out = String::new();
    for (t, kind) in tallies.iter().zip(["checkpoints", "films", "scenes"]) {
        out.push_str(&t.line(kind));
        out.push('\n');
        for e in &t.examples {
            out.push_str(&format!("    {e}\n"));
        }
    }
    out
}

#[test]
fn damaged_inputs_are_refused_or_harmless() {
    let tallies = fuzz(SUITE_CASES);
    let text = report(&tallies);
    for t in &tallies {
        assert_eq!(t.bad(), 0, "\n{text}");
        assert!(
            t.counts.get(&Verdict::Refused).copied().unwrap_or(0) > 0,
            "no case was refused: the mutations reach nothing\n{text}"
        );
    }
    // Resealed edits reach behind the header checksums (to the settings'
    // check, the identity, the typed fields), so those are tested too.
    for (t, kind) in [
        (&tallies[0], "header value, resealed"),
        (&tallies[1], "header number, resealed"),
        (&tallies[1], "header word, resealed"),
        (&tallies[1], "every part relabelled, resealed"),
    ] {
        let &(cases, checksum) = t.by_kind.get(kind).unwrap_or(&(0, 0));
        assert!(
            cases > 0 && checksum == 0,
            "{kind}: {cases} cases, {checksum} stopped by a checksum\n{text}"
        );
    }
}

/// The counts for the closing note (any binary, any case count).
#[test]
#[ignore = "a report: run with --ignored --nocapture"]
fn fuzz_report() {
    let cases = std::env::var("STRATA_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300);
    let tallies = fuzz(cases);
    println!(
        "{} ({cases} cases each)\n{}",
        binary().display(),
        report(&tallies)
    );
}
