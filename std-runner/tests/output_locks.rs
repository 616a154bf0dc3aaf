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
//!    output changes; new rows are appended and do not change it.
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
    let one = golden::render_hash(&data, strata_runner::render::SamplerKind::Sobol, 1).unwrap();
    assert_eq!(Some(one), golden::expected("cover", "sobol"));
}

/// The revision pin: (revision, rows, digest of those first rows). When
/// `OUTPUT_REVISION` is raised, pin it again over the whole table.
const PIN: (u32, usize, u64) = (2, 48, 0x7eab3799ac7085ad);

/// Merges refuse parts of another revision, so the revision is what keeps
/// parts with different pixels apart: an existing row may change only
/// with a new revision; rows may be added (at the end) without one.
#[test]
fn existing_rows_change_only_with_the_output_revision() {
    let (revision, rows, digest) = PIN;
    assert_eq!(
        strata::render::OUTPUT_REVISION,
        revision,
        "OUTPUT_REVISION changed: pin the whole table again (revision, row count, digest)"
    );
    assert!(
        golden::GOLDEN.len() >= rows,
        "golden rows were removed: users' outputs of revision {revision} are no longer checked"
    );
    let pinned: String = golden::GOLDEN[..rows].iter().map(row_text).collect();
    assert_eq!(
        fnv(&pinned),
        digest,
        "a row of revision {revision} changed, or rows were inserted before its end \
         (append new rows instead). {CHANGED}"
    );
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
