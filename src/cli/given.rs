//! Which flags the command line gave, from clap's own record of where each value came from
//! (`ArgMatches::value_source`): the kept settings fill in only what the user did not say.

use clap::parser::ValueSource;
use clap::ArgMatches;

/// The ids (clap's: the field names, `wind_dir` for `--wind-dir`) of the arguments given on
/// the command line, as opposed to taken from their defaults.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Given {
    ids: Vec<String>,
}

impl Given {
    /// What `matches` (one command's) says was given on the command line.
    pub fn of(matches: &ArgMatches) -> Self {
        let ids = matches
            .ids()
            .filter(|id| matches.value_source(id.as_str()) == Some(ValueSource::CommandLine))
            .map(|id| id.as_str().to_string())
            .collect();
        Self { ids }
    }

    /// Whether the argument `id` was given.
    pub fn has(&self, id: &str) -> bool {
        self.ids.iter().any(|g| g == id)
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use crate::cli::{parse_from, Cli, Command};

    #[test]
    fn flags_on_the_command_line_are_told_from_defaults() {
        // `--choppiness 1` is its default's value, given: it counts.
        let cli = parse_from([
            "vr-ocean",
            "xr",
            "--wind",
            "9",
            "--deck-height=4",
            "--choppiness",
            "1",
        ]);
        let Some(Command::Xr(a)) = cli.command else {
            panic!("not the xr command");
        };
        for id in ["wind", "deck_height", "choppiness"] {
            assert!(a.view.given.has(id), "{id} was given");
        }
        for id in ["wind_dir", "preset", "volume"] {
            assert!(!a.view.given.has(id), "{id} was not given");
        }
        let cli = parse_from(["vr-ocean", "window"]);
        let Some(Command::Window(a)) = cli.command else {
            panic!("not the window command");
        };
        assert_eq!(a.view.given, super::Given::default());
    }

    /// The ids the kept settings ask about (`cli/settings.rs`, `cli/view.rs`) name real
    /// arguments: a renamed flag fails here instead of silently overriding the user's flag.
    #[test]
    fn the_ids_the_settings_ask_about_are_arguments() {
        let cli = Cli::command();
        for (sub, ids) in [
            (
                "window",
                &["wind", "wind_dir", "choppiness", "preset", "volume"][..],
            ),
            (
                "xr",
                &[
                    "wind",
                    "wind_dir",
                    "choppiness",
                    "preset",
                    "volume",
                    "deck_height",
                ][..],
            ),
        ] {
            let cmd = cli.find_subcommand(sub).expect(sub);
            let known: Vec<&str> = cmd.get_arguments().map(|a| a.get_id().as_str()).collect();
            for id in ids {
                assert!(known.contains(id), "`{sub}` has no argument `{id}`");
            }
        }
    }
}
