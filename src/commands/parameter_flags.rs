//! The rendering parameters' command-line flags, made from the descriptor
//! table ([`pointblend::frame::parameters::TABLE`]): one `--FLAG VALUE` per
//! row (plus its `--no-…` switch where it has one), with the row's help, the
//! default taken from [`RenderSettings::default`] and the modes that read it
//! taken from the mode registry. A value is checked by the row's own parser
//! when clap reads it, so a bad one is refused before anything loads, in the
//! same words bench variants and sidecars get. No flag here is written by
//! hand: a new row is a new flag.

use clap::{Arg, ArgAction, ArgMatches, Command};
use pointblend::frame::{Parameter, RenderMode, RenderSettings};

/// The rendering parameters given on the command line, in the table's order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParameterFlags {
    given: Vec<Given>,
}

/// One parameter given on the command line.
#[derive(Debug, Clone, PartialEq)]
struct Given {
    parameter: Parameter,
    value: String,
    /// The flag it was given by (`--no-cull` or `--cull`), for messages.
    flag: &'static str,
}

/// The help of a row: what it does, its values, its default and its modes.
fn help_of(parameter: Parameter) -> String {
    let row = parameter.info();
    let default = parameter.text(&RenderSettings::default()).unwrap_or_else(|| "the mode's own".to_string());
    let modes: Vec<&str> = parameter.used_by().map(RenderMode::name).collect();
    format!("{}; values: {} [default: {default}] (read by {})", sentence(row.help), row.values, modes.join(", "))
}

/// `text` with an ASCII first letter capitalised (a Greek one, as in "ε of
/// the depth test", stays as it is written).
fn sentence(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_ascii_uppercase().to_string() + chars.as_str(),
        None => String::new(),
    }
}

impl ParameterFlags {
    /// The value given for `parameter`, if any.
    pub fn given(&self, parameter: Parameter) -> Option<&str> {
        self.given.iter().find(|g| g.parameter == parameter).map(|g| g.value.as_str())
    }

    /// Every parameter given, with its value (in the table's order).
    pub fn values(&self) -> Vec<(Parameter, String)> {
        self.given.iter().map(|g| (g.parameter, g.value.clone())).collect()
    }

    /// Sets every given parameter in `settings` (already checked by clap).
    pub fn apply(&self, settings: &mut RenderSettings) -> Result<(), String> {
        self.given.iter().try_for_each(|g| g.parameter.apply(settings, &g.value))
    }

    /// Logs each given flag `mode` does not read.
    pub fn warn_ignored(&self, mode: RenderMode) {
        for given in self.given.iter().filter(|g| !mode.reads(g.parameter)) {
            log::warn!("--{} is ignored: mode {mode} does not use it", given.flag);
        }
    }
}

impl clap::FromArgMatches for ParameterFlags {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let mut flags = ParameterFlags::default();
        flags.update_from_arg_matches(matches)?;
        Ok(flags)
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        for parameter in Parameter::ALL {
            let row = parameter.info();
            let value = matches.get_one::<String>(row.flag).cloned();
            let switch = row.off_switch.filter(|s| matches.get_flag(s));
            let (value, flag) = match (value, switch) {
                (Some(value), _) => (value, row.flag),
                (None, Some(switch)) => ("off".to_string(), switch),
                (None, None) => continue,
            };
            self.given.retain(|g| g.parameter != parameter);
            self.given.push(Given { parameter, value, flag });
        }
        Ok(())
    }
}

impl clap::Args for ParameterFlags {
    fn augment_args(mut command: Command) -> Command {
        for parameter in Parameter::ALL {
            let row = parameter.info();
            let check = move |text: &str| -> Result<String, String> {
                parameter.apply(&mut RenderSettings::default(), text).map(|()| text.to_string())
            };
            command = command.arg(
                Arg::new(row.flag)
                    .long(row.flag)
                    .value_name("VALUE")
                    .help(help_of(parameter))
                    .allow_negative_numbers(true)
                    .value_parser(check)
                    .help_heading("Rendering parameters"),
            );
            if let Some(switch) = row.off_switch {
                command = command.arg(
                    Arg::new(switch)
                        .long(switch)
                        .action(ArgAction::SetTrue)
                        .help(format!("--{} off", row.flag))
                        .conflicts_with(row.flag)
                        .help_heading("Rendering parameters"),
                );
            }
        }
        command
    }

    fn augment_args_for_update(command: Command) -> Command {
        Self::augment_args(command)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{Args, FromArgMatches};

    fn parse(args: &[&str]) -> Result<ParameterFlags, clap::Error> {
        let command = ParameterFlags::augment_args(Command::new("t").no_binary_name(true));
        ParameterFlags::from_arg_matches(&command.try_get_matches_from(args)?)
    }

    #[test]
    fn every_row_is_a_flag_that_reaches_the_settings() {
        let flags = parse(&["--depth-step", "2", "--no-cull", "--group", "wgc-k6", "--shadows", "tsm-64"]).unwrap();
        let mut settings = RenderSettings::default();
        flags.apply(&mut settings).unwrap();
        assert_eq!(settings.depth_step, 2.0);
        assert!(!settings.backface_culling);
        assert_eq!(settings.grouping.to_string(), "wgc-k6");
        assert_eq!(settings.shadows.cells, [64, 64]);
        let error = parse(&["--epsilon", "-1"]).unwrap_err().to_string();
        assert!(error.contains("epsilon=-1: expected a positive multiple"), "{error}");
        assert!(parse(&["--cull", "on", "--no-cull"]).is_err(), "a switch and its flag conflict");
    }
}
