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

/// A command line clap cannot take as it is.
#[derive(Debug, PartialEq)]
pub struct UsageError(pub String);

/// Rewrites `-name` to `--name` for every long option and checks that every option is
/// known. Values of options that take one, numbers (`-5`) and everything after `--`
/// are left alone; `-o`, `-h` and `-V` stay short options.
pub fn normalise(args: &[String], longs: &[LongOption]) -> Result<Vec<String>, UsageError> {
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
    Ok(out)
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
        normalise(&v, &longs())
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
