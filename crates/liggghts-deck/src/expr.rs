//! Equal-style variable formulas (`variable a equal 2*${r}+sqrt(v_b)`): numbers, `PI`,
//! `v_name`, `+ - * / % ^`, unary `- !`, comparisons `< <= > >= == !=`, `&& ||`, parentheses,
//! and the math functions of LAMMPS (`sqrt exp ln log abs sin cos tan asin acos atan atan2
//! floor ceil round`), with LAMMPS's precedence (`^` binds tighter than unary minus, right
//! associative). Names that only a running simulation knows — thermo keywords (`step*dt`),
//! `c_ID[i]`, `f_ID[i]` and per-atom values by tag (`vx[1]`) — are handed to the resolver as
//! a [`Ref`]; while a deck is read they are errors, while the DEM runs it answers them.

/// A name in a formula that the caller resolves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ref<'a> {
    /// `v_name`: another variable.
    Variable(&'a str),
    /// A bare word that is not a function or `PI`: a thermo keyword (`step`, `dt`, `atoms`…).
    Keyword(&'a str),
    /// `c_ID` (index `None`) or `c_ID[i]` (i ≥ 1): a compute's scalar or vector element.
    Compute(&'a str, Option<usize>),
    /// `f_ID` or `f_ID[i]`: a fix's scalar or vector element.
    Fix(&'a str, Option<usize>),
    /// `name[tag]`: a per-atom value (`x`, `vx`, `fx`, `mass`…) of the atom with that tag.
    Atom(&'a str, u64),
}

impl std::fmt::Display for Ref<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let idx = |i: &Option<usize>| i.map(|i| format!("[{i}]")).unwrap_or_default();
        match self {
            Ref::Variable(n) => write!(f, "v_{n}"),
            Ref::Keyword(n) => write!(f, "{n}"),
            Ref::Compute(n, i) => write!(f, "c_{n}{}", idx(i)),
            Ref::Fix(n, i) => write!(f, "f_{n}{}", idx(i)),
            Ref::Atom(n, t) => write!(f, "{n}[{t}]"),
        }
    }
}

/// Evaluates `text`; `resolve` answers the names in it ([`Ref`]).
pub fn evaluate(text: &str, resolve: &dyn Fn(Ref) -> Result<f64, String>) -> Result<f64, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        pos: 0,
        lookup: resolve,
    };
    let v = p.or()?;
    p.skip_ws();
    if p.pos != p.s.len() {
        return Err(format!(
            "unexpected `{}` in formula `{text}`",
            &text[p.pos..]
        ));
    }
    Ok(v)
}

struct Parser<'a> {
    s: &'a [u8],
    pos: usize,
    lookup: &'a dyn Fn(Ref) -> Result<f64, String>,
}

fn truth(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

impl Parser<'_> {
    fn skip_ws(&mut self) {
        while self.pos < self.s.len() && self.s[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn eat(&mut self, tok: &str) -> bool {
        self.skip_ws();
        if self.s[self.pos..].starts_with(tok.as_bytes()) {
            self.pos += tok.len();
            true
        } else {
            false
        }
    }

    fn or(&mut self) -> Result<f64, String> {
        let mut a = self.and()?;
        while self.eat("||") {
            let b = self.and()?;
            a = truth(a != 0.0 || b != 0.0);
        }
        Ok(a)
    }

    fn and(&mut self) -> Result<f64, String> {
        let mut a = self.cmp()?;
        while self.eat("&&") {
            let b = self.cmp()?;
            a = truth(a != 0.0 && b != 0.0);
        }
        Ok(a)
    }

    fn cmp(&mut self) -> Result<f64, String> {
        let mut a = self.sum()?;
        loop {
            a = if self.eat("<=") {
                truth(a <= self.sum()?)
            } else if self.eat(">=") {
                truth(a >= self.sum()?)
            } else if self.eat("==") {
                truth(a == self.sum()?)
            } else if self.eat("!=") {
                truth(a != self.sum()?)
            } else if self.eat("<") {
                truth(a < self.sum()?)
            } else if self.eat(">") {
                truth(a > self.sum()?)
            } else {
                return Ok(a);
            };
        }
    }

    fn sum(&mut self) -> Result<f64, String> {
        let mut a = self.product()?;
        loop {
            if self.eat("+") {
                a += self.product()?;
            } else if self.eat("-") {
                a -= self.product()?;
            } else {
                return Ok(a);
            }
        }
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut a = self.unary()?;
        loop {
            if self.eat("*") {
                a *= self.unary()?;
            } else if self.eat("/") {
                let b = self.unary()?;
                if b == 0.0 {
                    return Err("division by zero in formula".into());
                }
                a /= b;
            } else if self.eat("%") {
                a %= self.unary()?;
            } else {
                return Ok(a);
            }
        }
    }

    fn unary(&mut self) -> Result<f64, String> {
        if self.eat("-") {
            return Ok(-self.unary()?);
        }
        if self.eat("!") {
            return Ok(truth(self.unary()? == 0.0));
        }
        self.power()
    }

    fn power(&mut self) -> Result<f64, String> {
        let base = self.atom()?;
        if self.eat("^") {
            let e = self.unary()?;
            return Ok(base.powf(e));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<f64, String> {
        self.skip_ws();
        if self.eat("(") {
            let v = self.or()?;
            if !self.eat(")") {
                return Err("missing `)` in formula".into());
            }
            return Ok(v);
        }
        let start = self.pos;
        let c = *self.s.get(self.pos).ok_or("formula ends too early")?;
        if c.is_ascii_digit() || c == b'.' {
            while self.pos < self.s.len() {
                let c = self.s[self.pos];
                let exp_sign = (c == b'+' || c == b'-')
                    && self.pos > start
                    && matches!(self.s[self.pos - 1], b'e' | b'E');
                if c.is_ascii_digit() || c == b'.' || c == b'e' || c == b'E' || exp_sign {
                    self.pos += 1;
                } else {
                    break;
                }
            }
            let t = std::str::from_utf8(&self.s[start..self.pos]).unwrap_or("");
            return t
                .parse()
                .map_err(|_| format!("bad number `{t}` in formula"));
        }
        while self.pos < self.s.len()
            && (self.s[self.pos].is_ascii_alphanumeric() || self.s[self.pos] == b'_')
        {
            self.pos += 1;
        }
        let name = std::str::from_utf8(&self.s[start..self.pos]).unwrap_or("");
        if name.is_empty() {
            return Err(format!("unexpected `{}` in formula", c as char));
        }
        if self.s.get(self.pos) == Some(&b'[') {
            let close = self.s[self.pos..]
                .iter()
                .position(|&c| c == b']')
                .ok_or_else(|| format!("missing `]` after {name}["))?;
            let inner = std::str::from_utf8(&self.s[self.pos + 1..self.pos + close]).unwrap_or("");
            self.pos += close + 1;
            let index: u64 = inner
                .trim()
                .parse()
                .ok()
                .filter(|&i| i >= 1)
                .ok_or_else(|| {
                    format!("`{name}[{inner}]`: the index must be a whole number ≥ 1")
                })?;
            let r = match (name.strip_prefix("c_"), name.strip_prefix("f_")) {
                (Some(id), _) => Ref::Compute(id, Some(index as usize)),
                (_, Some(id)) => Ref::Fix(id, Some(index as usize)),
                _ if name.starts_with("v_") => {
                    return Err(format!(
                        "`{name}[{inner}]`: vector variables are not supported"
                    ))
                }
                _ => Ref::Atom(name, index),
            };
            return (self.lookup)(r);
        }
        if let Some(v) = name.strip_prefix("v_") {
            return (self.lookup)(Ref::Variable(v));
        }
        if let Some(id) = name.strip_prefix("c_") {
            return (self.lookup)(Ref::Compute(id, None));
        }
        if let Some(id) = name.strip_prefix("f_") {
            return (self.lookup)(Ref::Fix(id, None));
        }
        if name == "PI" {
            return Ok(std::f64::consts::PI);
        }
        if !self.eat("(") {
            return (self.lookup)(Ref::Keyword(name));
        }
        let a = self.or()?;
        let b = if self.eat(",") {
            Some(self.or()?)
        } else {
            None
        };
        if !self.eat(")") {
            return Err(format!("missing `)` after {name}("));
        }
        let one = |f: fn(f64) -> f64| -> Result<f64, String> {
            match b {
                None => Ok(f(a)),
                Some(_) => Err(format!("{name}() takes one argument")),
            }
        };
        match name {
            "sqrt" => one(f64::sqrt),
            "exp" => one(f64::exp),
            "ln" => one(f64::ln),
            "log" => one(f64::log10),
            "abs" => one(f64::abs),
            "sin" => one(f64::sin),
            "cos" => one(f64::cos),
            "tan" => one(f64::tan),
            "asin" => one(f64::asin),
            "acos" => one(f64::acos),
            "atan" => one(f64::atan),
            "floor" => one(f64::floor),
            "ceil" => one(f64::ceil),
            "round" => one(f64::round),
            "atan2" => b
                .map(|x| a.atan2(x))
                .ok_or_else(|| "atan2() takes two arguments".to_string()),
            _ => Err(format!("unknown function `{name}()` in formula")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str) -> Result<f64, String> {
        evaluate(s, &|n| match n {
            Ref::Variable("r") => Ok(0.5),
            Ref::Keyword("step") => Ok(200.0),
            Ref::Keyword("dt") => Ok(1e-5),
            Ref::Compute("com", Some(3)) => Ok(0.25),
            Ref::Fix("cfd2", Some(i)) => Ok(i as f64),
            Ref::Compute("rke", None) => Ok(7.0),
            Ref::Atom("vx", 1) => Ok(-3.0),
            other => Err(format!("no {other}")),
        })
    }

    #[test]
    fn precedence_like_lammps() {
        assert_eq!(ev("1+2*3").unwrap(), 7.0);
        assert_eq!(ev("-2^2").unwrap(), -4.0);
        assert_eq!(ev("2^3^2").unwrap(), 512.0);
        assert_eq!(ev("(1+2)*v_r").unwrap(), 1.5);
        assert_eq!(ev("1e-3*2").unwrap(), 2e-3);
        assert_eq!(ev("2.5E+1").unwrap(), 25.0);
        assert!((ev("sqrt(2)*PI").unwrap() - 2f64.sqrt() * std::f64::consts::PI).abs() < 1e-15);
        assert_eq!(ev("3 > 2 && 1 == 1").unwrap(), 1.0);
        assert!(ev("v_q").unwrap_err().contains("no v_q"));
        assert!(ev("1/0").is_err());
    }

    #[test]
    fn runtime_names_go_to_the_resolver() {
        assert_eq!(ev("step*dt").unwrap(), 200.0 * 1e-5);
        assert_eq!(ev("c_com[3]*2").unwrap(), 0.5);
        assert_eq!(ev("f_cfd2[2]+f_cfd2[3]").unwrap(), 5.0);
        assert_eq!(ev("c_rke").unwrap(), 7.0);
        assert_eq!(ev("-vx[1]").unwrap(), 3.0);
        assert!(ev("atoms").unwrap_err().contains("no atoms"));
        assert!(ev("f_x").unwrap_err().contains("no f_x"));
        assert!(ev("vx[0]").unwrap_err().contains("≥ 1"));
        assert!(ev("vx[1").unwrap_err().contains("missing `]`"));
        assert!(ev("v_a[2]").unwrap_err().contains("vector variables"));
    }
}
