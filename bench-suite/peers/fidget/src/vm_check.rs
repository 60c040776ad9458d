//! Checks a `.vm` tape against the grammar that fidget's `Context::from_text` reads,
//! so that a malformed file gives one error line instead of a panic inside fidget
//! (which unwraps missing words and unparsable constants).
//!
//! fidget's rules: a line that is empty or starts with `#` is skipped; otherwise its
//! first word names the value, the second is the opcode, then come the operands (a
//! number for `const`, earlier names otherwise). Extra words are ignored by fidget and
//! accepted here too.

/// Operand count of each opcode that fidget's text reader knows.
fn arity(op: &str) -> Option<usize> {
    Some(match op {
        "var-x" | "var-y" | "var-z" => 0,
        "const" | "abs" | "neg" | "sqrt" | "square" | "floor" | "ceil" | "round" | "sin"
        | "cos" | "tan" | "asin" | "acos" | "atan" | "ln" | "not" | "rand" | "exp" => 1,
        "add" | "mul" | "min" | "max" | "div" | "atan2" | "sub" | "compare" | "mod" | "and"
        | "or" | "mix" => 2,
        _ => return None,
    })
}

/// `Ok(())` when fidget can read `text` without panicking; otherwise a message naming
/// the 1-based line and what is wrong.
pub fn check(text: &str) -> Result<(), String> {
    let mut seen = std::collections::HashSet::new();
    let mut any = false;
    for (n, line) in text.lines().enumerate() {
        let n = n + 1;
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let (name, op) = match words.as_slice() {
            [name, op, ..] => (*name, *op),
            [] => {
                return Err(format!(
                    "line {n}: blank line with spaces (fidget rejects it)"
                ))
            }
            [_] => return Err(format!("line {n}: missing opcode")),
        };
        let want = arity(op).ok_or_else(|| format!("line {n}: unknown opcode '{op}'"))?;
        let args = &words[2..];
        if args.len() < want {
            return Err(format!(
                "line {n}: '{op}' takes {want} operand(s), found {}",
                args.len()
            ));
        }
        if op == "const" {
            if args[0].parse::<f64>().is_err() {
                return Err(format!("line {n}: '{}' is not a number", args[0]));
            }
        } else if let Some(a) = args[..want].iter().find(|a| !seen.contains(**a)) {
            return Err(format!("line {n}: '{a}' is not defined on an earlier line"));
        }
        seen.insert(name.to_owned());
        any = true;
    }
    if any {
        Ok(())
    } else {
        Err("no instructions (empty tape)".to_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::check;

    #[test]
    fn accepts_a_sphere() {
        let t = "# sphere\n_x var-x\n_y var-y\n_z var-z\n_a square _x\n_b square _y\n\
                 _c square _z\n_s add _a _b\n_t add _s _c\n_1 const 1\n_o sub _t _1\n";
        assert_eq!(check(t), Ok(()));
    }

    #[test]
    fn names_the_line_of_each_fault() {
        let cases = [
            ("_x var-x\n_y\n", "line 2: missing opcode"),
            (
                "_x var-x\n_y add _x\n",
                "line 2: 'add' takes 2 operand(s), found 1",
            ),
            ("_c const one\n", "line 1: 'one' is not a number"),
            (
                "_x var-x\n_y sub _x _q\n",
                "line 2: '_q' is not defined on an earlier line",
            ),
            ("_x frobnicate\n", "line 1: unknown opcode 'frobnicate'"),
            (
                "_x var-x\n   \n",
                "line 2: blank line with spaces (fidget rejects it)",
            ),
            ("# only a comment\n", "no instructions (empty tape)"),
        ];
        for (text, want) in cases {
            assert_eq!(check(text), Err(want.to_owned()), "{text:?}");
        }
    }
}
