//! The compile tools' spellings on top of clap: every long option also works with one
//! dash (`-sd 16`, `-lowpriority`, `-logfile F`), and an unknown option is named with
//! the nearest known one (`-savesample` → "did you mean -savesamples?") instead of
//! clap's reading of it as a bundle of short flags ("unexpected argument '-l'").

use clap::Command;

/// A long option of the command line.
#[derive(Debug, Clone)]
pub struct LongOption {
    pub name: String,
    /// The next word is its value (unless given as `--name=value`).
    pub takes_value: bool,
}

/// The long options (and their aliases) of `cmd`, plus `help` and `version`.
pub fn long_options(cmd: &Command) -> Vec<LongOption> {
    let mut v = vec![
        LongOption {
            name: "help".into(),
            takes_value: false,
        },
        LongOption {
            name: "version".into(),
            takes_value: false,
        },
    ];
    for a in cmd.get_arguments().filter(|a| !a.is_positional()) {
        // An optional value must be attached with `=`; the next word stays a map.
        let takes_value = a.get_action().takes_values() && !a.is_require_equals_set();
        let names = a
            .get_long()
            .into_iter()
            .chain(a.get_all_aliases().into_iter().flatten());
        for name in names {
            v.push(LongOption {
                name: name.to_string(),
                takes_value,
            });
        }
    }
    v
}

/// A command line that cannot be run (an unknown option, an impossible value, a
/// missing map, an output that would destroy an input): exit status 2, before any
/// compile starts, no `.err` file.
#[derive(Debug, PartialEq)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// `bail!` for command-line errors: returns a [`UsageError`] as an `anyhow::Error`.
macro_rules! usage {
    ($($arg:tt)*) => {
        return Err(anyhow::Error::new($crate::cli::args::UsageError(format!($($arg)*))))
    };
}
pub(crate) use usage;

/// Options of the map compile tools (VHLT/ZHLT, ericw-tools) that mean nothing to
/// bsp2vdg but sit in the shared flag set of a compile chain (`$common` in a J.A.C.K.
/// or Hammer profile): accepted and ignored with one warning, so one flag set serves
/// every tool. The flag says whether the option takes a value.
pub const COMPILE_TOOL_FLAGS: &[(&str, bool)] = &[
    ("texdata", true),
    ("lightdata", true),
    ("console", true),
    ("chop", true),
    ("texchop", true),
    ("maxnodesize", true),
    ("wadinclude", true),
    ("cliptype", true),
    ("noinfo", false),
    ("wadautodetect", false),
    ("nowadtextures", false),
    ("nocolor", false),
    ("notjunc", false),
    ("extra", false),
    ("extra4", false),
];

/// A command line in clap's spelling, and the compile-tool options it ignores.
#[derive(Debug, PartialEq)]
pub struct Normalised {
    pub args: Vec<String>,
    /// The ignored options as given (with their values), for the warning line.
    pub ignored: Vec<String>,
}

/// Rewrites `-name` to `--name` for every long option and checks that every option is
/// known. Values of options that take one, numbers (`-5`) and everything after `--`
/// are left alone; `-o`, `-h` and `-V` stay short options; the compile tools' options
/// of [`COMPILE_TOOL_FLAGS`] are taken out.
pub fn normalise(args: &[String], longs: &[LongOption]) -> Result<Normalised, UsageError> {
    let mut ignored = Vec::new();
    let mut out = Vec::with_capacity(args.len());
    let mut words = args.iter();
    if let Some(program) = words.next() {
        out.push(program.clone());
    }
    let find = |name: &str| longs.iter().find(|o| o.name == name);
    while let Some(a) = words.next() {
        let is_option = a.len() > 1 && a.starts_with('-') && a.parse::<f64>().is_err();
        if a == "--" {
            out.push(a.clone());
            out.extend(words.by_ref().cloned());
            break;
        }
        if !is_option {
            out.push(a.clone());
            continue;
        }
        let (double, body) = match a.strip_prefix("--") {
            Some(b) => (true, b),
            None => (false, &a[1..]),
        };
        let (name, attached) = match body.split_once('=') {
            Some((n, _)) => (n, true),
            None => (body, false),
        };
        if !double && matches!(name, "h" | "V") {
            out.push(a.clone());
            continue;
        }
        if !double && name.starts_with('o') && find(name).is_none() {
            // -o FILE, or -oFILE as clap allows.
            out.push(a.clone());
            if name == "o"
                && !attached
                && let Some(v) = words.next()
            {
                out.push(v.clone());
            }
            continue;
        }
        let tool_flag = COMPILE_TOOL_FLAGS.iter().find(|(n, _)| *n == name);
        if let (None, Some(&(_, takes_value))) = (find(name), tool_flag) {
            let mut given = a.clone();
            if takes_value
                && !attached
                && let Some(v) = words.next()
            {
                given = format!("{given} {v}");
            }
            ignored.push(given);
            continue;
        }
        let Some(option) = find(name) else {
            return Err(unknown(a, double, name, longs));
        };
        out.push(format!("--{body}"));
        if option.takes_value
            && !attached
            && let Some(v) = words.next()
        {
            out.push(v.clone());
        }
    }
    Ok(Normalised { args: out, ignored })
}

fn unknown(word: &str, double: bool, name: &str, longs: &[LongOption]) -> UsageError {
    let dash = if double { "--" } else { "-" };
    let nearest = longs
        .iter()
        .map(|o| (strsim::damerau_levenshtein(name, &o.name), &o.name))
        .filter(|(d, o)| *d <= (name.len().max(o.len()) / 3).max(2))
        .min();
    let hint = match nearest {
        Some((_, o)) => format!(" (did you mean {dash}{o}?)"),
        None => String::new(),
    };
    UsageError(format!(
        "unknown option {word}{hint}; bsp2vdg --help lists the options"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn longs() -> Vec<LongOption> {
        [
            ("sd", true),
            ("savesamples", false),
            ("low", false),
            ("lowpriority", false),
            ("logfile", true),
            ("json", false),
            ("source-name", false),
        ]
        .iter()
        .map(|&(n, t)| LongOption {
            name: n.into(),
            takes_value: t,
        })
        .collect()
    }

    fn norm(a: &[&str]) -> Result<Vec<String>, UsageError> {
        let v: Vec<String> = a.iter().map(|s| s.to_string()).collect();
        normalise(&v, &longs()).map(|n| n.args)
    }

    #[test]
    fn compile_tool_flags_are_taken_out_with_their_values() {
        let v: Vec<String> = [
            "b",
            "-texdata",
            "8192",
            "-noinfo",
            "-sd",
            "16",
            "-console",
            "0",
            "-chop",
            "64",
            "-wadautodetect",
            "m.bsp",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let n = normalise(&v, &longs()).unwrap();
        assert_eq!(n.args, ["b", "--sd", "16", "m.bsp"]);
        assert_eq!(
            n.ignored,
            [
                "-texdata 8192",
                "-noinfo",
                "-console 0",
                "-chop 64",
                "-wadautodetect"
            ]
        );
        // Not a compile-tool flag: still an error.
        assert!(norm(&["b", "-texdat", "1", "m.bsp"]).is_err());
    }

    #[test]
    fn single_dash_long_options_become_double() {
        assert_eq!(
            norm(&[
                "b",
                "-sd",
                "-4",
                "-savesamples",
                "-o",
                "-x.vdg",
                "-5",
                "--json",
                "-lowpriority",
                "-logfile",
                "-l.txt",
                "m.bsp",
                "--source-name=a",
                "--",
                "-weird.bsp"
            ])
            .unwrap(),
            [
                "b",
                "--sd",
                "-4",
                "--savesamples",
                "-o",
                "-x.vdg",
                "-5",
                "--json",
                "--lowpriority",
                "--logfile",
                "-l.txt",
                "m.bsp",
                "--source-name=a",
                "--",
                "-weird.bsp"
            ]
        );
    }

    #[test]
    fn unknown_options_name_the_nearest() {
        let e = norm(&["b", "-savesample", "m.bsp"]).unwrap_err();
        assert_eq!(
            e.0,
            "unknown option -savesample (did you mean -savesamples?); bsp2vdg --help lists the options"
        );
        let e = norm(&["b", "--jsn"]).unwrap_err();
        assert!(e.0.contains("did you mean --json?"), "{}", e.0);
        let e = norm(&["b", "-frobnicate"]).unwrap_err();
        assert!(!e.0.contains("did you mean"), "{}", e.0);
        assert!(e.0.starts_with("unknown option -frobnicate"), "{}", e.0);
    }
}
