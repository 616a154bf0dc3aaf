//! `strata verify`: the golden table re-rendered, one line per row.

use anyhow::{Result, bail};

use crate::cli::VerifyArgs;
use crate::golden;
use crate::image_io::say;

/// Runs `strata verify`: one line per row of the golden table (renders,
/// scene hashes, file bytes), and an error if any differs.
pub fn verify(args: &VerifyArgs) -> Result<()> {
    say(&format!(
        "{}: golden rows (renders {}x{}, {} spp, seed {}, depth {}; scene hashes; file bytes)",
        crate::version_line(),
        golden::SIZE.0,
        golden::SIZE.1,
        golden::SPP,
        golden::SEED,
        golden::DEPTH
    ));
    let outcomes = golden::verify(args.threads as usize, &mut |o| {
        let (status, why) = match o.expected {
            Some(e) if e == o.got => ("pass", String::new()),
            Some(e) => ("FAIL", format!("  (expected {e:016x})")),
            None => ("FAIL", "  (not in the table)".to_string()),
        };
        say(&format!(
            "{status}  {:<32} {:<22} {:016x}{why}",
            o.scene, o.key, o.got
        ));
    })?;
    let failed = outcomes.iter().filter(|o| !o.pass()).count();
    if failed > 0 {
        bail!(
            "{failed} of {} golden rows differ: this build or machine does not reproduce \
             Strata {}'s output",
            outcomes.len(),
            crate::film::version()
        );
    }
    say(&format!("all {} golden rows match", outcomes.len()));
    Ok(())
}
