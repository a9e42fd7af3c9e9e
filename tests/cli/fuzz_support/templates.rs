//! The valid command lines of each command, and what else each command takes.

use super::text::strings;

/// A valid command line and what else its command takes.
pub struct Template {
    pub words: &'static [&'static str],
    pub positional: Option<&'static str>,
    /// Flags of the valid line; `None`: a switch.
    pub flags: &'static [(&'static str, Option<&'static str>)],
    /// Other flags the command takes, with a valid value.
    pub extra: &'static [(&'static str, &'static str)],
    /// Flags that cannot be left out.
    pub required: &'static [&'static str],
    /// Flags whose repeats add values (`--hold 1 --hold 2`).
    pub repeatable: &'static [&'static str],
    /// Pairs of flags that exclude each other.
    pub exclusive: &'static [(&'static str, &'static str)],
}

pub const TEMPLATES: &[Template] = &[
    Template {
        words: &["run"],
        positional: Some("s.toml"),
        flags: &[
            ("-o", Some("out.h5")),
            ("--threads", Some("1")),
            ("--max-steps", Some("200")),
            ("-q", None),
        ],
        extra: &[
            ("--step-limit", "1000000"),
            ("--halo-skin", "0.25"),
            ("--rebalance-threshold", "0.2"),
        ],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["info"],
        positional: Some("run.h5"),
        flags: &[],
        extra: &[],
        required: &[],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["render"],
        positional: Some("run.h5"),
        flags: &[
            ("-o", Some("pictures")),
            ("--snapshot", Some("1")),
            ("--color", Some("speed")),
        ],
        extra: &[("--every", "2")],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[("--snapshot", "--every")],
    },
    Template {
        words: &["compare"],
        positional: Some("s.toml"),
        flags: &[
            ("-o", Some("cmp")),
            ("--laws", Some("amontons,rate")),
            ("--reference-slip-speed", Some("0.01")),
            ("--threads", Some("1")),
            ("-q", None),
        ],
        extra: &[
            ("--amontons-mu", "0.5"),
            ("--profile-bins", "25"),
            ("--slip-jump", "10"),
            ("--slip-min-rate", "0.001"),
        ],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[("--reference-slip-speed", "--amontons-mu")],
    },
    Template {
        words: &["sweep"],
        positional: Some("s.toml"),
        flags: &[
            ("--set", Some("friction.mu=0.3,0.6")),
            ("-o", Some("sweep")),
            ("--threads", Some("1")),
        ],
        extra: &[
            ("--profile-bins", "25"),
            ("--slip-jump", "10"),
            ("--slip-min-rate", "0.001"),
        ],
        required: &["-o"],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["slider", "hold"],
        positional: None,
        flags: &[
            ("--preset", Some("lab")),
            ("--hold", Some("1,10")),
            ("--dt", Some("0.001")),
            ("--normal-load", Some("2000")),
        ],
        extra: &[
            ("--step-limit", "100000000"),
            ("--form", "regularized"),
            ("--state-law", "aging"),
        ],
        required: &["--preset"],
        repeatable: &["--hold"],
        exclusive: &[],
    },
    Template {
        words: &["slider", "step"],
        positional: None,
        flags: &[
            ("--preset", Some("tank")),
            ("--from", Some("0.001")),
            ("--to", Some("0.01")),
            ("--dt", Some("0.001")),
            ("--json", None),
        ],
        extra: &[
            ("--normal-load", "10000"),
            ("--step-limit", "100000000"),
            ("--form", "regularized"),
            ("--state-law", "aging"),
        ],
        required: &["--preset", "--from", "--to"],
        repeatable: &[],
        exclusive: &[],
    },
    Template {
        words: &["slider", "run"],
        positional: Some("p.toml"),
        flags: &[("--out", Some("out"))],
        extra: &[("--step-limit", "100000000")],
        required: &["--out"],
        repeatable: &[],
        exclusive: &[],
    },
];

/// A command line being mutated.
#[derive(Clone)]
pub struct Line {
    pub positional: Option<String>,
    pub flags: Vec<(String, Option<String>)>,
}

impl Line {
    pub fn of(template: &Template) -> Line {
        Line {
            positional: template.positional.map(String::from),
            flags: template
                .flags
                .iter()
                .map(|(f, v)| (f.to_string(), v.map(String::from)))
                .collect(),
        }
    }

    pub fn args(&self, template: &Template) -> Vec<String> {
        let mut args = strings(template.words);
        args.extend(self.positional.clone());
        for (flag, value) in &self.flags {
            args.push(flag.clone());
            args.extend(value.clone());
        }
        args
    }

    pub fn has(&self, flag: &str) -> bool {
        self.flags.iter().any(|(f, _)| f == flag)
    }
}
