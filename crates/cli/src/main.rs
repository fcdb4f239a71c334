//! The `hxai` command line: simulate recordings, compute the physics model and features,
//! fit, apply and evaluate hybrid models, run symbolic regression and the Table 3 baselines
//! on any table.
//!
//! Every subcommand lives in its own module with an `Args` struct (clap) and a
//! `run(args, &Global) -> anyhow::Result<()>` function. Only this crate prints.

use anyhow::Result;
use clap::{Parser, Subcommand};

mod compare;
mod displacement;
mod dynamic;
mod evaluate;
mod explain;
mod features;
mod fit;
mod hybrid;
mod one_record;
mod predict;
mod progress;
mod records;
mod report;
mod safety;
mod simulate;
mod sr;
mod strategy;
mod stream;

/// Options shared by every subcommand.
#[derive(Debug, Clone, clap::Args)]
pub struct Global {
    /// Worker threads for parallel work (default: all cores). Results never depend on it.
    #[arg(long, global = true)]
    pub threads: Option<usize>,
    /// The separator of CSV cells (`,`, `;`, `tab`, or any one character; default: found
    /// from the header line, `,` before `;` before a tab).
    #[arg(long, global = true, value_parser = parse_delimiter)]
    pub delimiter: Option<char>,
    /// The decimal mark of numbers in CSV files: `.` (default) or `,` (a European CSV,
    /// `0,05`; the cells must then be separated by another character, e.g. `;`).
    #[arg(long, global = true, value_parser = parse_decimal)]
    pub decimal: Option<char>,
    /// Numbers your files write for a missing value (`-9999,9.96921e36`): every cell of a
    /// table or record equal to one (within 1e-6 of its size) is read as empty, and
    /// `--missing` decides what happens to it. Default: none.
    #[arg(long, global = true, value_delimiter = ',', allow_hyphen_values = true, value_parser = parse_code)]
    pub missing_codes: Vec<f64>,
}

fn parse_code(s: &str) -> Result<f64, String> {
    s.trim().parse::<f64>().map_err(|_| {
        format!("{s:?} is not a number: give codes such as --missing-codes=-9999,-999")
    })
}

fn parse_delimiter(s: &str) -> Result<char, String> {
    match s {
        "tab" | "\\t" | "\t" => Ok('\t'),
        _ => {
            let mut c = s.chars();
            match (c.next(), c.next()) {
                (Some(d), None) if d != '"' && d != '\n' && d != '\r' => Ok(d),
                _ => Err(format!(
                    "{s:?} is not one character: give the separator, e.g. --delimiter ';' or --delimiter tab"
                )),
            }
        }
    }
}

fn parse_decimal(s: &str) -> Result<char, String> {
    match s {
        "." => Ok('.'),
        "," => Ok(','),
        _ => Err(format!("{s:?}: the decimal mark is `.` or `,`")),
    }
}

#[derive(Debug, Parser)]
#[command(
    name = "hxai",
    version,
    about = "Hybrid physics + explainable AI modelling"
)]
struct Cli {
    #[command(flatten)]
    global: Global,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Write a simulated data folder (manifest + records).
    Simulate(simulate::Args),
    /// Physics-model displacement of one record.
    ///
    /// --frequency-hz must lie inside the pass band; the command's amplitude and phase in the
    /// physics displacement are reported (least-squares sine fit).
    Displacement(displacement::Args),
    /// The twelve features of one record.
    ///
    /// --frequency-hz is feature f1.
    Features(features::Args),
    /// Fit a hybrid model on a data folder.
    Fit(fit::Args),
    /// Apply a fitted hybrid model to one record.
    Predict(predict::Args),
    /// Physics vs hybrid on the records of a data folder.
    Evaluate(evaluate::Args),
    /// Apply a fitted hybrid model sample by sample to a CSV stream of acceleration
    /// (standard input or --in), one output row per sample, causally.
    ///
    /// The row of each sample depends on that sample and the ones before it only (delay 0);
    /// the first rows (one model window) are the warm-up, with empty values. A gap or a jump
    /// back in time restarts the estimator with a warning; a bad line stops the run with an
    /// error naming it, after every row before it has been written.
    Stream(stream::Args),
    /// Pictures (SVG) of a fitted model's correction: its response to each feature, predicted
    /// vs true with prediction intervals, and the Pareto front it was chosen from.
    Explain(explain::Args),
    /// One self-contained HTML page of a table hybrid (model, scores, alternatives,
    /// figures, warnings, how to refit).
    Report(report::Args),
    /// Symbolic regression on any CSV table.
    Sr(sr::Args),
    /// Table 3 baselines and the symbolic model on a train/test table pair.
    Compare(compare::Args),
    /// Hybrid models of any process on a table: physics equation + symbolic correction.
    Hybrid(Box<hybrid::Args>),
    /// Grey-box dynamic models: the engineer's ODE, calibrated through its trajectories,
    /// with a learned correction inside the derivative (docs/dynamic.md).
    Dynamic(Box<dynamic::Args>),
}

fn main() {
    safety::exit_quietly_on_broken_pipe();
    let (cli, flags) = parse();
    #[cfg(unix)]
    let installed = safety::remove_temporary_files_on_signal();
    #[cfg(not(unix))]
    let installed: Result<()> = Ok(());
    let result = installed.and_then(|()| run(cli));
    safety::wait_if_stopping();
    // cells emptied by --missing-codes that no command said yet (before a refusal of them)
    safety::note_missing_codes();
    if let Err(e) = result {
        // One line on stderr: the reason, with its causes (each said once).
        #[allow(clippy::print_stderr)]
        {
            eprintln!(
                "error: {}",
                safety::flag_names(&safety::one_line(&e), &flags)
            );
        }
        std::process::exit(1);
    }
}

/// The command line with every option that takes a value accepting a negative number
/// (`--interval -0.5` reaches the option's own check and its message, instead of clap's
/// "unexpected argument '-0'").
fn command() -> clap::Command {
    fn negative_values(c: clap::Command) -> clap::Command {
        c.mut_args(|a| {
            if a.get_action().takes_values() && !a.is_positional() {
                a.allow_negative_numbers(true)
            } else {
                a
            }
        })
        .mut_subcommands(negative_values)
    }
    use clap::CommandFactory;
    negative_values(Cli::command())
}

/// Ends the process with clap's report of a bad command line, the parse errors of Rust's
/// integers said in words (`--seed -1` is "not a whole number of 0 or more", not "invalid
/// digit found in string").
fn exit_with(e: &clap::Error) -> ! {
    if e.kind() != clap::error::ErrorKind::ValueValidation {
        e.exit();
    }
    let text = e
        .render()
        .to_string()
        .replace(
            "invalid digit found in string",
            "not a whole number of 0 or more",
        )
        .replace(
            "number too large to fit in target type",
            "too large a whole number",
        );
    #[allow(clippy::print_stderr)]
    {
        eprint!("{text}");
    }
    std::process::exit(e.exit_code());
}

/// The parsed command line and the long options of the subcommand that runs (for
/// [`safety::flag_names`]).
fn parse() -> (Cli, Vec<String>) {
    use clap::FromArgMatches;
    let cmd = command();
    let matches = cmd
        .clone()
        .try_get_matches()
        .unwrap_or_else(|e| exit_with(&e));
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| exit_with(&e));
    let (mut c, mut m) = (&cmd, &matches);
    while let Some((name, sub)) = m.subcommand() {
        match c.find_subcommand(name) {
            Some(next) => (c, m) = (next, sub),
            None => break,
        }
    }
    let flags = c
        .get_arguments()
        .filter_map(|a| a.get_long().map(str::to_owned))
        .collect();
    (cli, flags)
}

fn run(cli: Cli) -> Result<()> {
    if let Some(n) = cli.global.threads {
        anyhow::ensure!(
            (1..=safety::MAX_THREADS).contains(&n),
            "--threads must be 1 to {}, got {n}",
            safety::MAX_THREADS
        );
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| anyhow::anyhow!("cannot set up {n} threads: {e}"))?;
    }
    if cli.global.delimiter.is_some() || cli.global.decimal.is_some() {
        let d = hxai_data::CsvDialect {
            delimiter: cli.global.delimiter,
            decimal: cli.global.decimal.unwrap_or('.'),
        };
        anyhow::ensure!(
            !(d.decimal == ',' && d.delimiter == Some(',')),
            "--decimal , with --delimiter ,: a comma cannot both separate cells and mark \
             decimals; European CSV files separate cells with `;` (--delimiter ';')"
        );
        hxai_data::set_csv_dialect(d);
    }
    if !cli.global.missing_codes.is_empty() {
        hxai_data::set_missing_codes(cli.global.missing_codes.clone())
            .map_err(anyhow::Error::msg)?;
    }
    let g = &cli.global;
    match cli.command {
        Command::Simulate(a) => simulate::run(a, g),
        Command::Displacement(a) => displacement::run(a, g),
        Command::Features(a) => features::run(a, g),
        Command::Fit(a) => fit::run(a, g),
        Command::Predict(a) => predict::run(a, g),
        Command::Stream(a) => stream::run(a, g),
        Command::Evaluate(a) => evaluate::run(a, g),
        Command::Explain(a) => explain::run(a, g),
        Command::Report(a) => report::run(a, g),
        Command::Sr(a) => sr::run(a, g),
        Command::Compare(a) => compare::run(a, g),
        Command::Hybrid(a) => hybrid::run(*a, g),
        Command::Dynamic(a) => dynamic::run(*a, g),
    }
}

#[cfg(test)]
mod tests {
    /// clap checks the whole command tree (every subcommand's names, aliases, conflicts)
    /// only when a subcommand is parsed in a debug build; this checks all of it at once, so a
    /// renamed argument left in a `conflicts_with` list fails here and not in a user's hands.
    #[test]
    fn the_command_line_definition_is_consistent() {
        super::command().debug_assert();
    }

    /// A negative or huge whole number is refused in words.
    #[test]
    fn whole_numbers_are_refused_in_words() {
        let e = super::command()
            .try_get_matches_from([
                "hxai", "sr", "--csv", "t.csv", "--target", "y", "--epochs", "-1",
            ])
            .err()
            .map(|e| e.render().to_string())
            .unwrap_or_default();
        assert!(
            e.contains("invalid digit"),
            "clap's own words, which exit_with replaces: {e}"
        );
    }

    /// A negative number reaches the option's own check (`--interval -0.5` is "must lie
    /// strictly between 0 and 1"), not clap's "unexpected argument '-0'".
    #[test]
    fn negative_numbers_are_values() {
        use clap::FromArgMatches;
        let m = super::command().try_get_matches_from([
            "hxai", "sr", "--csv", "t.csv", "--target", "y", "--seed", "-1",
        ]);
        let e = m.map_err(|e| e.to_string()).err().unwrap_or_default();
        assert!(!e.contains("unexpected argument"), "{e}");
        let m = super::command().try_get_matches_from([
            "hxai",
            "hybrid",
            "compare",
            "--data",
            "t.csv",
            "--target",
            "y",
            "--physics",
            "x",
            "--interval",
            "-0.5",
        ]);
        let cli = m.ok().and_then(|m| super::Cli::from_arg_matches(&m).ok());
        assert!(cli.is_some());
    }
}
