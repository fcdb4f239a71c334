//! Reading the records of a data folder for `fit` and `evaluate`, both of which need the
//! ground truth of every record they read.

use anyhow::{Context, Result};
use hxai_data::{DataFolder, ManifestEntry, Record};
use hxai_hybrid::records::RecordInput;
use indicatif::ProgressBar;

/// Reads `entries` of `folder`, ticking `pb`; every record must carry `probe_um`, which
/// `purpose` ("fitting", "evaluating") needs.
pub fn read_with_truth(
    folder: &DataFolder,
    entries: &[&ManifestEntry],
    purpose: &str,
    pb: &ProgressBar,
) -> Result<Vec<Record>> {
    let mut recs = Vec::with_capacity(entries.len());
    for e in entries {
        let r = folder
            .read_record(e)
            .with_context(|| format!("cannot read record `{}`", e.record))?;
        anyhow::ensure!(
            r.probe_um.is_some(),
            "record `{}` ({}) has no `probe_um` column; {purpose} needs the ground truth",
            e.record,
            folder.path_of(e).display()
        );
        recs.push(r);
        pb.inc(1);
    }
    pb.finish_and_clear();
    Ok(recs)
}

/// The composer's view of each record: id and commanded frequency from the manifest,
/// sampling rate and channels from the file.
pub fn inputs<'a>(entries: &[&'a ManifestEntry], recs: &'a [Record]) -> Vec<RecordInput<'a>> {
    entries
        .iter()
        .zip(recs)
        .map(|(e, r)| RecordInput {
            id: &e.record,
            fs_hz: r.fs_hz(),
            frequency_hz: e.frequency_hz,
            signal: &r.accel_ms2,
            truth: r.probe_um.as_deref(),
        })
        .collect()
}

/// Warnings for records whose probe amplitude is far from the manifest's commanded
/// amplitude (a probe in mm, a wrong manifest row).
pub fn amplitude_warnings(entries: &[&ManifestEntry], inputs: &[RecordInput<'_>]) -> Vec<String> {
    entries
        .iter()
        .zip(inputs)
        .filter_map(|(e, r)| hxai_hybrid::records::amplitude_warning(r, e.amplitude_um))
        .map(|w| w.to_string())
        .collect()
}
