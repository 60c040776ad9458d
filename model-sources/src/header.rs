//! The header of a model file: comment lines that state the model's domain box and
//! view, so a file renders as its author meant without flags.
//!
//! ```text
//! # domain: XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX
//! # view: eye=X,Y,Z look-at=X,Y,Z up=X,Y,Z fov=DEGREES ortho=WIDTH
//! ```
//!
//! The comment mark is the format's (`#` for formula and `.vm` files); the key follows
//! it after optional blanks, then `:`. Such lines may stand anywhere in the file, each
//! key at most once. A `view:` line names any of its fields, separated by blanks;
//! those left out come from the view that frames the domain
//! ([`model_ir::camera::frame_box`]). `ortho=WIDTH` makes the view orthographic, `WIDTH`
//! model units across the image. Other comment lines are plain comments. Flags on the
//! command line override what the header states.

use glam::DVec3;
use model_ir::shape::{check_domain, Aabb, View};

/// What a header states; `None` where it is silent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Header {
    /// `domain:`.
    pub domain: Option<Aabb>,
    /// `view:`, field by field.
    pub view: ViewFields,
}

/// The fields a `view:` line gives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViewFields {
    /// `eye=X,Y,Z`.
    pub eye: Option<DVec3>,
    /// `look-at=X,Y,Z`.
    pub look_at: Option<DVec3>,
    /// `up=X,Y,Z`.
    pub up: Option<DVec3>,
    /// `fov=DEGREES`.
    pub fov_deg: Option<f64>,
    /// `ortho=WIDTH`.
    pub ortho: Option<f64>,
}

impl ViewFields {
    /// Whether no field is given.
    pub fn is_empty(&self) -> bool {
        *self == ViewFields::default()
    }

    /// `base` with the given fields replaced.
    pub fn apply(&self, mut base: View) -> View {
        if let Some(v) = self.eye {
            base.eye = v;
        }
        if let Some(v) = self.look_at {
            base.look_at = v;
        }
        if let Some(v) = self.up {
            base.up = v;
        }
        if let Some(v) = self.fov_deg {
            base.fov_deg = v;
        }
        if self.ortho.is_some() {
            base.ortho = self.ortho;
        }
        base
    }
}

impl Header {
    /// The header of `text`, whose comments start with `comment`; errors are
    /// `path:line:column: message`, the column counted in characters.
    pub fn parse(text: &str, comment: &str, path: &str) -> Result<Header, String> {
        let mut h = Header::default();
        let (mut seen_domain, mut seen_view) = (false, false);
        for (k, line) in text.lines().enumerate() {
            let body = line.trim_start();
            let Some(rest) = body.strip_prefix(comment) else {
                continue;
            };
            let after = rest.trim_start();
            let Some((key, value)) = after.split_once(':') else {
                continue;
            };
            let key = key.trim_end();
            if key != "domain" && key != "view" {
                continue;
            }
            // Column (1-based, in characters) of the value's first character.
            let value_col = line.chars().count() - value.chars().count() + 1;
            let at = |col: usize, msg: String| format!("{path}:{}:{col}: {msg}", k + 1);
            let lead = value.chars().take_while(|c| c.is_whitespace()).count();
            let value_trim = value.trim();
            if key == "domain" {
                if seen_domain {
                    return Err(at(value_col, "a second 'domain:' header line".into()));
                }
                seen_domain = true;
                let v = numbers(value_trim, 6)
                    .map_err(|m| at(value_col + lead, format!("domain: {m}")))?;
                let b = Aabb::new(DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]));
                check_domain(&b).map_err(|e| at(value_col + lead, format!("domain: {e}")))?;
                h.domain = Some(b);
            } else {
                if seen_view {
                    return Err(at(value_col, "a second 'view:' header line".into()));
                }
                seen_view = true;
                h.view = view_fields(value, value_col, &at)?;
            }
        }
        Ok(h)
    }
}

/// `n` comma-separated finite numbers.
fn numbers(s: &str, n: usize) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != n {
        return Err(format!(
            "expected {n} comma-separated numbers, got {} in '{s}'",
            parts.len()
        ));
    }
    parts
        .iter()
        .map(|p| match p.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("'{p}' is not a finite number")),
        })
        .collect()
}

/// The fields of a `view:` value starting at column `col0`.
fn view_fields(
    value: &str,
    col0: usize,
    at: &dyn Fn(usize, String) -> String,
) -> Result<ViewFields, String> {
    let mut f = ViewFields::default();
    let chars: Vec<char> = value.chars().collect();
    let mut i = 0;
    let mut any = false;
    while i < chars.len() {
        if chars[i].is_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len() && !chars[i].is_whitespace() {
            i += 1;
        }
        any = true;
        let word: String = chars[start..i].iter().collect();
        let col = col0 + start;
        let Some((key, val)) = word.split_once('=') else {
            return Err(at(
                col,
                format!("view: expected KEY=VALUE (eye, look-at, up, fov, ortho), found '{word}'"),
            ));
        };
        let vcol = col + key.chars().count() + 1;
        let vec3 = |val: &str| -> Result<DVec3, String> {
            let v = numbers(val, 3).map_err(|m| at(vcol, format!("view: {key}: {m}")))?;
            Ok(DVec3::new(v[0], v[1], v[2]))
        };
        let positive = |val: &str| -> Result<f64, String> {
            match val.parse::<f64>() {
                Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
                _ => Err(at(
                    vcol,
                    format!("view: {key}: '{val}' is not a positive number"),
                )),
            }
        };
        let dup = |set: bool| -> Result<(), String> {
            if set {
                Err(at(col, format!("view: '{key}' given twice")))
            } else {
                Ok(())
            }
        };
        match key {
            "eye" => {
                dup(f.eye.is_some())?;
                f.eye = Some(vec3(val)?);
            }
            "look-at" => {
                dup(f.look_at.is_some())?;
                f.look_at = Some(vec3(val)?);
            }
            "up" => {
                dup(f.up.is_some())?;
                f.up = Some(vec3(val)?);
            }
            "fov" => {
                dup(f.fov_deg.is_some())?;
                let v = positive(val)?;
                if v >= 180.0 {
                    return Err(at(vcol, format!("view: fov: {v} is not below 180 degrees")));
                }
                f.fov_deg = Some(v);
            }
            "ortho" => {
                dup(f.ortho.is_some())?;
                f.ortho = Some(positive(val)?);
            }
            _ => {
                return Err(at(
                    col,
                    format!("view: unknown key '{key}' (expected eye, look-at, up, fov or ortho)"),
                ))
            }
        }
    }
    if !any {
        return Err(at(
            col0,
            "view: expected KEY=VALUE fields (eye, look-at, up, fov, ortho)".into(),
        ));
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_and_errors() {
        let h = Header::parse(
            "# a plain comment\n#domain: -1,-1,-1, 1,1,1\nx\n  # view: ortho=3 eye=0,0,5\n",
            "#",
            "f.expr",
        )
        .unwrap();
        assert_eq!(h.domain, Some(Aabb::cube(1.0)));
        assert_eq!(h.view.ortho, Some(3.0));
        assert_eq!(h.view.eye, Some(DVec3::new(0.0, 0.0, 5.0)));
        assert!(h.view.look_at.is_none());
        let e = |t: &str| Header::parse(t, "#", "f").unwrap_err();
        assert_eq!(
            e("x\n# domain: 1,2,3"),
            "f:2:11: domain: expected 6 comma-separated numbers, got 3 in '1,2,3'"
        );
        assert_eq!(
            e("# view: eye=0,0,5 fog=3"),
            "f:1:19: view: unknown key 'fog' (expected eye, look-at, up, fov or ortho)"
        );
        assert_eq!(
            e("# view: ortho=-1"),
            "f:1:15: view: ortho: '-1' is not a positive number"
        );
        assert!(e("# domain: 1,1,1,0,0,0").starts_with("f:1:11: domain: "));
        assert!(e("# view: up=1\n").starts_with("f:1:12: view: up: expected 3"));
        assert!(e("# view: fov=3\n# view: fov=4").starts_with("f:2:"));
        // Another format's comment mark leaves `#` lines alone.
        assert_eq!(
            Header::parse("# view: nonsense", "--", "f").unwrap(),
            Header::default()
        );
    }
}
