//! The HyperFun lexer: tokens with their line and column, following the reference
//! scanner (`int_scanner.c` of the HyperFun interpreter): `--` comments to the end of
//! the line, case-insensitive names (folded to lower case), keywords, and the operator
//! characters of the language.

use super::HfError;

/// One token of a HyperFun program.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A number literal.
    Num(f64),
    /// A name, in lower case (HyperFun names are case-insensitive).
    Name(String),
    /// A string literal (only library functions the subset does not have take them).
    Str(String),
    /// A keyword: `array if then else endif while loop endloop and or not xor`.
    Key(&'static str),
    /// An operator or punctuation: `^ + - ~ / * & | \ @ , ; = ( ) [ ] { } < > <= >= /=`.
    Sym(&'static str),
    /// The end of the program.
    End,
}

/// A token and where it starts (1-based line and column, in characters).
#[derive(Clone, Debug)]
pub(crate) struct Token {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
}

const KEYWORDS: [&str; 12] = [
    "array", "if", "then", "else", "endif", "while", "loop", "endloop", "and", "or", "not", "xor",
];

/// Operators, the two-character ones first.
const SYMBOLS: [&str; 24] = [
    "<=", ">=", "/=", "^", "+", "-", "~", "/", "*", "&", "|", "\\", "@", ",", ";", "=", "(", ")",
    "[", "]", "{", "}", "<", ">",
];

/// The longest name or number accepted, as the reference scanner's string buffer.
pub(crate) const MAX_LEXEME: usize = 255;

/// Splits `src` into tokens; the last one is [`Tok::End`].
pub(crate) fn lex(src: &str) -> Result<Vec<Token>, HfError> {
    let chars: Vec<char> = src.chars().collect();
    let n = chars.len();
    let (mut i, mut line, mut col) = (0usize, 1usize, 1usize);
    let mut out = Vec::new();
    let err = |line, col, msg: String| Err(HfError::new(line, col, msg));
    while i < n {
        let c = chars[i];
        if c == '\n' {
            i += 1;
            line += 1;
            col = 1;
            continue;
        }
        if c.is_whitespace() {
            i += 1;
            col += 1;
            continue;
        }
        if c == '-' && chars.get(i + 1) == Some(&'-') {
            while i < n && chars[i] != '\n' {
                i += 1;
                col += 1;
            }
            continue;
        }
        let start = (line, col);
        let push = |out: &mut Vec<Token>, tok| {
            out.push(Token {
                tok,
                line: start.0,
                col: start.1,
            })
        };
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let s = i;
            while i < n && chars[i].is_ascii_digit() {
                i += 1;
            }
            if i < n && chars[i] == '.' {
                i += 1;
                while i < n && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            if i < n && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < n && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < n && chars[j].is_ascii_digit() {
                    i = j;
                    while i < n && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                } else {
                    return err(
                        line,
                        col + (i - s),
                        "invalid number: expected digits after the exponent mark".into(),
                    );
                }
            }
            let text: String = chars[s..i].iter().collect();
            if i < n && (chars[i].is_ascii_alphabetic() || chars[i] == '_' || chars[i] == '.') {
                return err(line, col, format!("invalid number '{text}{}'", chars[i]));
            }
            if text.len() > MAX_LEXEME {
                return err(line, col, "number too long".into());
            }
            let v: f64 = match text.parse() {
                Ok(v) if f64::is_finite(v) => v,
                _ => return err(line, col, format!("invalid number '{text}'")),
            };
            col += i - s;
            push(&mut out, Tok::Num(v));
            continue;
        }
        if c.is_ascii_alphabetic() {
            let s = i;
            while i < n && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            if i - s > MAX_LEXEME {
                return err(
                    line,
                    col,
                    format!("name longer than {MAX_LEXEME} characters"),
                );
            }
            let name: String = chars[s..i].iter().collect::<String>().to_ascii_lowercase();
            col += i - s;
            let tok = match KEYWORDS.iter().find(|k| **k == name) {
                Some(k) => Tok::Key(k),
                None => Tok::Name(name),
            };
            push(&mut out, tok);
            continue;
        }
        if c == '"' {
            let s = i + 1;
            let mut j = s;
            while j < n && chars[j] != '"' && chars[j] != '\n' {
                j += 1;
            }
            if j >= n || chars[j] != '"' {
                return err(line, col, "string without its closing '\"'".into());
            }
            let text: String = chars[s..j].iter().collect();
            col += j + 1 - i;
            i = j + 1;
            push(&mut out, Tok::Str(text));
            continue;
        }
        let rest = &chars[i..];
        let sym = SYMBOLS.iter().find(|s| {
            let k = s.chars().count();
            rest.len() >= k && s.chars().zip(rest.iter()).all(|(a, &b)| a == b)
        });
        match sym {
            Some(s) => {
                let k = s.chars().count();
                i += k;
                col += k;
                push(&mut out, Tok::Sym(s));
            }
            None => {
                return err(
                    line,
                    col,
                    format!("unexpected character '{}'", c.escape_debug()),
                )
            }
        }
    }
    out.push(Token {
        tok: Tok::End,
        line,
        col,
    });
    Ok(out)
}

/// How a token reads in an error message.
pub(crate) fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("number {v}"),
        Tok::Name(n) => format!("name '{n}'"),
        Tok::Str(s) => format!("string \"{s}\""),
        Tok::Key(k) => format!("'{k}'"),
        Tok::Sym(s) => format!("'{s}'"),
        Tok::End => "end of input".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_positions_and_comments() {
        let t = lex("My_Model(x[3], a[1]) -- comment\n{ f = -x[1]^2 <= 1.5e-1; }").unwrap();
        assert_eq!(t[0].tok, Tok::Name("my_model".into()));
        assert_eq!((t[0].line, t[0].col), (1, 1));
        let lbrace = t.iter().find(|t| t.tok == Tok::Sym("{")).unwrap();
        assert_eq!((lbrace.line, lbrace.col), (2, 1));
        assert!(t.iter().any(|t| t.tok == Tok::Sym("<=")));
        assert!(t.iter().any(|t| t.tok == Tok::Num(0.15)));
        assert_eq!(t.last().unwrap().tok, Tok::End);
        let e = lex("a = 2 $ 3").unwrap_err();
        assert_eq!((e.line, e.column), (1, 7));
        assert!(lex("x = 1e+").is_err() && lex("x = \"abc").is_err() && lex("2x").is_err());
    }
}
