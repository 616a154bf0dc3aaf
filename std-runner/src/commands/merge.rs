//! `strata merge`: partial films into one image or film, every part
//! checked before anything is written.

use anyhow::{Result, bail};

use crate::cli::MergeArgs;
use crate::commands::check_output_ext;
use crate::commands::output::{SppMap, check_output_or_film, same_path, write_film_or_image};
use crate::film::{is_film_path, merge_files, samples_text, window_text};
use crate::image_io::say;

/// Runs `strata merge`: every part is read and checked before the output
/// is written; a refused merge writes nothing.
pub fn merge(args: &MergeArgs) -> Result<()> {
    check_output_or_film(&args.output)?;
    if let Ok(out) = args.output.canonicalize()
        && let Some(p) = args
            .parts
            .iter()
            .find(|p| p.canonicalize().is_ok_and(|p| p == out))
    {
        bail!("the output `{}` is one of the parts", p.display());
    }
    if let Some(map) = &args.spp_map {
        check_output_ext(map, "png", "--spp-map")?;
        if same_path(map, &args.output) || args.parts.iter().any(|p| same_path(map, p)) {
            bail!(
                "--spp-map `{}` is the output or one of the parts",
                map.display()
            );
        }
    }
    // An image is of the finished render; a .film may be a staged part.
    // Headers first, then one body at a time: one image in memory.
    let film = merge_files(&args.parts, !is_film_path(&args.output))?;
    // Drawn before the image is written: a failure leaves no image.
    let map = args
        .spp_map
        .as_ref()
        .map(|_| SppMap::draw(&film))
        .transpose()?;
    write_film_or_image(&args.output, &film, args.gamma)?;
    if let (Some(path), Some(map)) = (&args.spp_map, &map)
        && let Err(e) = map.write(path)
    {
        std::fs::remove_file(&args.output).ok();
        return Err(e);
    }
    let whole = film.window == strata::render::Tile::whole(film.key.width(), film.key.height())
        && film.samples == (0..film.key.spp());
    let part = match whole {
        true => String::new(),
        false => format!(
            " (a staged part: pixels {}, samples {})",
            window_text(film.window),
            samples_text(&film.samples)
        ),
    };
    say(&format!(
        "merged {} part{}: {} {}x{}, {} spp{part}, to {}",
        args.parts.len(),
        if args.parts.len() == 1 { "" } else { "s" },
        film.key.get("scene").unwrap_or("?"),
        film.key.width(),
        film.key.height(),
        film.key.spp(),
        args.output.display()
    ));
    Ok(())
}
