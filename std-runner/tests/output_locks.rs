//! Output locks: every output byte Strata writes, checked on every
//! platform CI builds (x86-64 native and portable SSE2, aarch64 under
//! qemu). The core's own locks (streams, mappings, hits) are in
//! `core/tests/locks.rs`, which also runs on WebAssembly.
//!
//! 1. The golden table (`strata_runner::golden`, what `strata verify`
//!    checks): the exact film sums of small renders of every built-in scene
//!    and the example scene file under every sampler and six
//!    reconstruction variants; the content hash of every scene; and the
//!    exact bytes of a PNG, an EXR and a `.film` of each built-in scene.
//! 2. The versioning rule: `OUTPUT_REVISION` changes when an existing
//!    output changes; new rows are appended and do not change it (see
//!    [`PINS`]).
//!
//! These numbers were produced by this implementation and are a lock, not
//! a derivation. If a change trips them on purpose, every seeded render
//! (or file) changes: follow the message.

use strata_runner::golden;

const CHANGED: &str = "an output changed. If intended, raise strata::render::OUTPUT_REVISION, \
     update the table and the pin, and add a line under \"Output changes\" in CHANGELOG.md";

/// One golden row as the pin hashes it.
fn row_text((scene, key, hash): &(&str, &str, u64)) -> String {
    format!("{scene} {key} {hash:016x}\n")
}

fn fnv(text: &str) -> u64 {
    strata_runner::hash::fnv1a(text.as_bytes())
}

#[test]
fn golden_table_reproduces() {
    let outcomes = golden::verify(2, &mut |_| {}).unwrap();
    let failures: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.pass())
        .map(|o| {
            format!(
                "{} {}: {:016x} (locked {:?})",
                o.scene, o.key, o.got, o.expected
            )
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{}\nthe table is now:\n{}{CHANGED}",
        failures.join("\n"),
        golden::table_source(&outcomes)
    );
    assert_eq!(
        outcomes.len(),
        golden::GOLDEN.len(),
        "a table row has no outcome"
    );
    // Every row is checked once, in table order.
    for (o, row) in outcomes.iter().zip(golden::GOLDEN) {
        assert_eq!((o.scene.as_str(), o.key.as_str()), (row.0, row.1));
    }
    // One thread gives the same hash as two.
    let data = golden::scene("cover").unwrap();
    let one = golden::render_hash(&data, strata_runner::job::SamplerKind::Sobol, 1).unwrap();
    assert_eq!(Some(one), golden::expected("cover", "sobol"));
}

/// The pins: (output identity, rows, digest of the table's first `rows`
/// rows), oldest first. The identity is `film::version()`, the crate
/// version and `+rN` of `OUTPUT_REVISION` that film files carry: merges
/// refuse parts of another identity. Appending rows adds a pin of the same
/// identity; changing a row needs a new identity (a new revision, or a
/// release, whose version text is in every file) and a pin of it.
const PINS: &[(&str, usize, u64)] = &[
    ("0.1.0+r2", 31, 0x17a15c139b9f1176),
    ("0.1.0+r2", 48, 0x7eab3799ac7085ad),
    ("0.1.0+r3", 48, 0x8eda318d0976d991),
    ("0.1.0+r3", 53, 0xfbe7ba15dc9100ff),
    ("0.1.0+r3", 63, 0x958bba7c3db8c4c7),
    ("0.1.0+r4", 63, 0x0c7e6c6f35fb01e5),
    ("0.1.0+r5", 63, 0x5e4e546a041aca64),
    ("0.1.0+r6", 63, 0x5ee4e1c8d343b332),
    ("0.1.0+r7", 63, 0x8efb8df489c67dc2),
    ("0.1.0+r8", 63, 0xc41b3ab61c1b3920),
    ("0.1.0+r9", 63, 0x6761fa23923064c8),
    ("0.1.0+r10", 63, 0x974cf29982b444dd),
    ("0.1.0+r11", 63, 0x3f70d98431433532),
    ("0.1.0+r12", 63, 0x249c7a5a54e29ffb),
    ("0.1.0+r13", 63, 0xabfd94d1eca80d91),
    ("0.1.0+r14", 63, 0xece82666913ae5fb),
    ("0.1.0+r15", 63, 0xe6da4ef5e83c801f),
    ("0.1.0+r16", 63, 0xcb88ea54f1c6f9bf),
];

fn digest(rows: usize) -> u64 {
    fnv(&golden::GOLDEN[..rows]
        .iter()
        .map(row_text)
        .collect::<String>())
}

/// An existing row may change only with a new output identity, and rows
/// may be added (at the end) without one.
#[test]
fn existing_rows_change_only_with_a_new_output_identity() {
    let current = strata_runner::film::version();
    let &(last, rows, _) = PINS.last().unwrap();
    assert_eq!(
        last,
        current,
        "the output identity is now {current}: pin the whole table for it \
         (add (\"{current}\", {}, {:#018x}) to PINS)",
        golden::GOLDEN.len(),
        digest(golden::GOLDEN.len())
    );
    assert!(
        rows <= golden::GOLDEN.len(),
        "golden rows were removed: outputs of {current} are no longer checked"
    );
    assert_eq!(
        rows,
        golden::GOLDEN.len(),
        "rows were appended: pin them (add (\"{current}\", {}, {:#018x}) to PINS); \
         new rows keep the revision",
        golden::GOLDEN.len(),
        digest(golden::GOLDEN.len())
    );
    for &(identity, rows, want) in PINS {
        let matches = digest(rows) == want;
        if identity == current {
            assert!(
                matches,
                "a row pinned for {identity} changed, or rows were inserted before row {rows} \
                 (append new rows instead). {CHANGED}"
            );
        }
    }
    // An older identity's last pin must no longer match: a new revision
    // is for changed outputs, never for added ones.
    for (k, &(identity, rows, want)) in PINS.iter().enumerate() {
        let last_of_its_identity = PINS[k + 1..].iter().all(|p| p.0 != identity);
        if identity != current && last_of_its_identity {
            assert_ne!(
                digest(rows.min(golden::GOLDEN.len())),
                want,
                "{current} changes no row of {identity}: added rows keep the output identity"
            );
        }
    }
    // Keys are unique, so a row can be found by name.
    let mut keys: Vec<(&str, &str)> = golden::GOLDEN.iter().map(|r| (r.0, r.1)).collect();
    keys.sort_unstable();
    let n = keys.len();
    keys.dedup();
    assert_eq!(keys.len(), n, "a golden key appears twice");
}

/// The scene and file rows cover every scene and format the runner has.
#[test]
fn every_scene_and_file_format_is_locked() {
    for name in golden::scene_names() {
        assert!(
            golden::expected(name, "scene").is_some(),
            "{name}: no scene row"
        );
    }
    for name in strata_runner::scenes::BUILT_IN {
        for ext in golden::FILE_FORMATS {
            let key = format!("file.{ext}");
            assert!(
                golden::expected(name, &key).is_some(),
                "{name}: no {key} row"
            );
        }
    }
}

/// The golden rows other languages reproduce (the C API's tests, later
/// Python and the browser), as a data file written from the table, so
/// no hash is copied by hand: every built-in scene's film hash for every
/// sampler, with the golden render's settings as `strata render` flags.
/// `STRATA_BLESS=1` writes it after a deliberate change.
fn golden_json() -> String {
    let (w, h) = golden::SIZE;
    let mut out = String::from(
        "{\n  \"about\": \"Golden film hashes (FNV-1a 64 of the exact sums), written by std-runner/tests/output_locks.rs (golden_file_is_current) from std-runner/src/golden.rs.\",\n",
    );
    out += &format!(
        "  \"flags\": [\"--width\", \"{w}\", \"--height\", \"{h}\", \"--spp\", \"{}\", \"--seed\", \"{}\", \"--max-depth\", \"{}\"],\n",
        golden::SPP,
        golden::SEED,
        golden::DEPTH
    );
    out += "  \"films\": {\n";
    let rows: Vec<String> = golden::GOLDEN
        .iter()
        .filter(|(scene, key, _)| {
            strata_runner::scenes::BUILT_IN.contains(scene)
                && strata_runner::job::SamplerKind::ALL
                    .iter()
                    .any(|k| k.name() == *key)
        })
        .map(|(scene, key, hash)| format!("    \"{scene}/{key}\": \"{hash:#018x}\""))
        .collect();
    out += &rows.join(",\n");
    out += "\n  }\n}\n";
    out
}

#[test]
fn golden_file_is_current() {
    let want = golden_json();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/golden.json");
    if std::env::var_os("STRATA_BLESS").is_some() {
        std::fs::write(path, &want).unwrap();
    }
    let got = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        got == want,
        "std-runner/tests/data/golden.json differs from the golden table: run `STRATA_BLESS=1 cargo test -p strata-runner --test output_locks golden_file`"
    );
}
