//! Progress bars (indicatif) for long work: light paths traced and samples rendered, with rates.
//! Bars draw on stderr only when it is a terminal, so scripts and CI logs stay clean.

use indicatif::{ProgressBar, ProgressStyle};

/// A bar counting `total` items of `unit` (e.g. "paths"), showing the rate per second.
pub fn bar(total: u64, what: &str, unit: &str) -> ProgressBar {
    let pb = ProgressBar::new(total);
    let template = format!(
        "{what:>9} [{{elapsed_precise}}] {{bar:40.cyan/blue}} {{human_pos}}/{{human_len}} {unit} ({{per_sec}}, eta {{eta}})"
    );
    pb.set_style(
        ProgressStyle::with_template(&template).expect("static template is valid").progress_chars("=> "),
    );
    pb
}
