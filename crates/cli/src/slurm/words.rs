//! The values a user gives for the job scripts, checked before they are written: no
//! control character anywhere (a newline would end the `#SBATCH` line and start a shell
//! line), names (partition, account, QOS) by Slurm's syntax, time and memory by their
//! parsers; and the quoting of a value on an `#SBATCH` line.

use anyhow::bail;

/// Seconds of a Slurm time limit (`minutes`, `minutes:seconds`, `hours:minutes:seconds`,
/// `days-hours`, `days-hours:minutes`, `days-hours:minutes:seconds`).
pub fn parse_time(text: &str) -> anyhow::Result<u64> {
    let bad = || {
        anyhow::anyhow!(
            "time `{text}`: expected a positive Slurm time limit (`minutes`, `HH:MM:SS`, `D-HH:MM`, …)"
        )
    };
    let t = text.trim();
    let (days, rest) = match t.split_once('-') {
        Some((d, r)) => (Some(d), r),
        None => (None, t),
    };
    let num = |s: &str| -> anyhow::Result<u64> {
        if s.is_empty() || !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad());
        }
        s.parse().map_err(|_| bad())
    };
    let parts: Vec<u64> = rest.split(':').map(num).collect::<Result<_, _>>()?;
    let secs = match (days, parts.as_slice()) {
        (None, [m]) => m * 60,
        (None, [m, s]) => m * 60 + s,
        (None, [h, m, s]) => h * 3600 + m * 60 + s,
        (Some(d), [h]) => num(d)? * 86400 + h * 3600,
        (Some(d), [h, m]) => num(d)? * 86400 + h * 3600 + m * 60,
        (Some(d), [h, m, s]) => num(d)? * 86400 + h * 3600 + m * 60 + s,
        _ => return Err(bad()),
    };
    if secs == 0 {
        return Err(bad());
    }
    Ok(secs)
}

/// Megabytes of a Slurm memory size (`4096`, `4096M`, `4G`, `1T`; no unit: MB).
pub fn parse_mem(text: &str) -> anyhow::Result<u64> {
    let bad = || anyhow::anyhow!("mem `{text}`: expected a positive size such as `4G` or `4096M`");
    let t = text.trim();
    let (digits, scale) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => {
            let scale = match c.to_ascii_uppercase() {
                'K' => 1.0 / 1024.0,
                'M' => 1.0,
                'G' => 1024.0,
                'T' => 1024.0 * 1024.0,
                _ => return Err(bad()),
            };
            (&t[..i], scale)
        }
        _ => (t, 1.0),
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(bad());
    }
    let mb = (digits.parse::<f64>().map_err(|_| bad())? * scale).ceil() as u64;
    if mb == 0 {
        return Err(bad());
    }
    Ok(mb)
}

/// Refuse `value` (the setting `what`) when it holds a control character.
pub fn check_no_control(what: &str, value: &str) -> anyhow::Result<()> {
    if let Some(c) = value.chars().find(|c| c.is_control()) {
        bail!(
            "{what} `{}`: contains the control character {c:?}, which cannot go into a job script",
            value.escape_debug()
        );
    }
    Ok(())
}

/// Refuse `value` unless it is a Slurm name (partition, account, QOS): letters, digits,
/// `_`, `-` and `.`, or a comma-separated list of them when `list`.
pub fn check_name(what: &str, value: &str, list: bool) -> anyhow::Result<()> {
    check_no_control(what, value)?;
    let ok_name = |n: &str| {
        !n.is_empty()
            && n.chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c))
    };
    let ok = if list {
        value.split(',').all(ok_name)
    } else {
        ok_name(value)
    };
    if !ok {
        bail!(
            "{what} `{value}`: expected a Slurm name (letters, digits, `_`, `-`, `.`{})",
            if list {
                "; several separated by `,`"
            } else {
                ""
            }
        );
    }
    Ok(())
}

/// Check a further `sbatch` option: one argument, `--name[=value]` or `-Xvalue`, no
/// control character; the value of `--account`/`-A`, `--partition`/`-p`, `--qos`/`-q`,
/// `--time`/`-t`, `--mem` and `--mem-per-cpu` by Slurm's syntax.
pub fn check_sbatch_arg(arg: &str) -> anyhow::Result<()> {
    let what = "sbatch argument";
    check_no_control(what, arg)?;
    let (name, value) = if let Some(long) = arg.strip_prefix("--") {
        match long.split_once('=') {
            Some((n, v)) => (n, Some(v)),
            None => (long, None),
        }
    } else if let Some(short) = arg.strip_prefix('-') {
        let mut chars = short.chars();
        let Some(letter) = chars.next() else {
            bail!("{what} `{arg}`: expected an option such as `--account=gait`");
        };
        let rest = chars.as_str();
        (long_name(letter), (!rest.is_empty()).then_some(rest))
    } else {
        bail!("{what} `{arg}`: expected an option starting with `-`");
    };
    let name_ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if !name_ok || (value.is_none() && arg.contains(char::is_whitespace)) {
        bail!("{what} `{arg}`: expected one option, written `--name=value`");
    }
    let Some(v) = value else {
        return Ok(());
    };
    let what = format!("{what} `{arg}`");
    match name {
        "account" | "partition" | "qos" => check_name(name, v, name == "partition"),
        "time" | "time-min" => parse_time(v).map(|_| ()),
        "mem" | "mem-per-cpu" => parse_mem(v).map(|_| ()),
        _ => Ok(()),
    }
    .map_err(|e| e.context(what))
}

/// The long option of the short `sbatch` options whose values are checked.
fn long_name(letter: char) -> &'static str {
    match letter {
        'A' => "account",
        'p' => "partition",
        'q' => "qos",
        't' => "time",
        _ => "short",
    }
}

/// `value` as one word of an `#SBATCH` line: as it is when it holds only letters, digits
/// and `-_=.,:/%+@`, else in double quotes, with `\` and `"` escaped by a backslash
/// (sbatch reads quotes and backslashes on these lines; an unquoted `#` would start a
/// comment, a space would split the word). Control characters must have been refused
/// before.
pub fn sbatch_word(value: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_=.,:/%+@".contains(c);
    if !value.is_empty() && value.chars().all(plain) {
        return value.to_string();
    }
    let mut s = String::from("\"");
    for c in value.chars() {
        if c == '"' || c == '\\' {
            s.push('\\');
        }
        s.push(c);
    }
    s.push('"');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_and_bad_names_are_refused() {
        let e = check_sbatch_arg("--account=x\nrm -rf ~/data").unwrap_err();
        assert!(
            format!("{e:#}").contains("control character '\\n'"),
            "{e:#}"
        );
        let e = check_name("partition", "a b;c", true).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("partition `a b;c`: expected a Slurm name"),
            "{e}"
        );
        check_name("partition", "gpu,cpu-long", true).unwrap();
        assert!(check_name("account", "a,b", false).is_err());
        for ok in [
            "--account=gait",
            "-Agait",
            "--comment=two words",
            "--exclusive",
            "--mem=4G",
        ] {
            check_sbatch_arg(ok).unwrap_or_else(|e| panic!("{ok}: {e:#}"));
        }
        for (bad, needle) in [
            ("--account=a;b", "expected a Slurm name"),
            ("-p a b", "expected a Slurm name"),
            ("--time=1h", "time `1h`"),
            ("--mem=lots", "mem `lots`"),
            ("-A x", "expected a Slurm name"),
            ("--no such", "expected one option"),
            ("rm", "starting with `-`"),
            ("--x=\r", "control character"),
        ] {
            let e = format!("{:#}", check_sbatch_arg(bad).unwrap_err());
            assert!(e.contains(needle), "{bad}: {e}");
        }
    }

    #[test]
    fn words_are_quoted_for_sbatch() {
        assert_eq!(
            sbatch_word("--comment=a \"b\" #c\\"),
            r#""--comment=a \"b\" #c\\""#
        );
        assert_eq!(sbatch_word("--account=gait"), "--account=gait");
        assert_eq!(
            sbatch_word("--output=/a b/%x.out"),
            "\"--output=/a b/%x.out\""
        );
    }
}
