//! What the terminal can show: the glyphs ([`Glyphs`]: ASCII or Unicode, from `TERM` unless
//! overridden), the colour depth told by the environment (`NO_COLOR`, `TERM`, `COLORTERM`), and
//! [`SgrFilter`], the writer between the backend and the terminal that
//! rewrites colours to that depth.
//!
//! The workbench draws with the 16 named colours only, but crossterm writes every named colour
//! as an indexed one (`Color::Red` as `ESC[38;5;9m`). A terminal without 256 colours reads
//! `38;5;9` as three attributes (38, then 5 blink, then 9 strike-through); with
//! [`ColorDepth::Ansi16`] the filter writes `ESC[91m` instead, and with [`ColorDepth::None`]
//! no colour at all.

use std::io::{self, Write};

/// How many colours the terminal shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorDepth {
    /// No colour: `NO_COLOR` set, or `TERM=dumb`.
    None,
    /// The 16 ANSI colours (SGR 30–37, 90–97, 40–47, 100–107): vt100, linux, xterm, screen, …
    Ansi16,
    /// 256 indexed colours: a `TERM` naming them (`xterm-256color`, `tmux-256color`, …).
    Ansi256,
    /// 24-bit colour: `COLORTERM=truecolor` or `24bit`.
    TrueColor,
}

impl ColorDepth {
    /// The depth told by the environment, read through `get` (a variable's value, None when
    /// unset): `NO_COLOR` (non-empty) → none; `TERM=dumb` → none; `COLORTERM` truecolor or
    /// 24bit → true colour; a `TERM` with `256color` → 256; any other `TERM`, or none → 16.
    pub fn from_vars(get: &dyn Fn(&str) -> Option<String>) -> ColorDepth {
        let set = |k: &str| get(k).filter(|v| !v.is_empty());
        if set("NO_COLOR").is_some() {
            return ColorDepth::None;
        }
        let term = set("TERM").unwrap_or_default().to_ascii_lowercase();
        if term == "dumb" {
            return ColorDepth::None;
        }
        let colorterm = set("COLORTERM").unwrap_or_default().to_ascii_lowercase();
        if colorterm == "truecolor" || colorterm == "24bit" || term.ends_with("-direct") {
            ColorDepth::TrueColor
        } else if term.contains("256col") {
            ColorDepth::Ansi256
        } else {
            ColorDepth::Ansi16
        }
    }

    /// The depth of this process's environment.
    pub fn from_env() -> ColorDepth {
        Self::from_vars(&|k| std::env::var(k).ok())
    }
}

/// The characters the workbench draws with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Glyphs {
    /// Nothing above 0x7E: `+ - |` borders, series by their marks, `-` for the zero line.
    Ascii,
    /// Braille charts, box drawing, blocks, Greek letters.
    Unicode,
}

/// The environment variable that overrides the glyphs told by `TERM`.
pub const GLYPHS_VAR: &str = "DECKSPIN_GLYPHS";

impl Glyphs {
    /// `ascii` or `unicode` (any case).
    pub fn parse(s: &str) -> Option<Glyphs> {
        match s.trim().to_ascii_lowercase().as_str() {
            "ascii" => Some(Glyphs::Ascii),
            "unicode" => Some(Glyphs::Unicode),
            _ => None,
        }
    }

    /// The glyphs a terminal of type `term` shows: ASCII for the terminals without Braille
    /// or box drawing in their character set (`dumb`, the Linux console `linux`, the DEC
    /// `vt52`, `vt100`, `vt102`, `vt220`, … and their variants such as `vt100-am`, `ansi`),
    /// Unicode for the others (`xterm*`, `screen*`, `tmux*`, `rxvt*`, …) and when `TERM` is
    /// unset.
    pub fn of_term(term: &str) -> Glyphs {
        let term = term.trim().to_ascii_lowercase();
        let family = term.split(['-', '+', '.']).next().unwrap_or("");
        let vt = family
            .strip_prefix("vt")
            .is_some_and(|n| n.starts_with(|c: char| c.is_ascii_digit()));
        if vt || matches!(family, "dumb" | "linux" | "ansi") {
            Glyphs::Ascii
        } else {
            Glyphs::Unicode
        }
    }

    /// The glyphs told by the environment read through `get`: `DECKSPIN_GLYPHS`
    /// (`ascii`/`unicode`) when set, else ASCII with `DECKSPIN_ASCII` set to anything but `0`,
    /// else [`Glyphs::of_term`]. An unknown `DECKSPIN_GLYPHS` is an error naming it.
    pub fn from_vars(get: &dyn Fn(&str) -> Option<String>) -> Result<Glyphs, String> {
        let set = |k: &str| get(k).filter(|v| !v.trim().is_empty());
        if let Some(v) = set(GLYPHS_VAR) {
            return Glyphs::parse(&v)
                .ok_or_else(|| format!("{GLYPHS_VAR}='{v}': expected ascii or unicode"));
        }
        if set("DECKSPIN_ASCII").is_some_and(|v| v.trim() != "0") {
            return Ok(Glyphs::Ascii);
        }
        Ok(Glyphs::of_term(&set("TERM").unwrap_or_default()))
    }
}

/// The longest escape sequence kept whole; a longer one is passed on as it is.
const MAX_SEQ: usize = 64;

/// A writer that rewrites the colours of SGR sequences (`ESC [ … m`) to a [`ColorDepth`]:
/// with 16 colours, indexed and RGB colours become the nearest of the 16 (30–37/90–97 for the
/// foreground, 40–47/100–107 for the background, underline colours dropped); with none, every
/// colour parameter is dropped (a sequence left with nothing is not written, never as a bare
/// `ESC[m`, which would reset bold and reverse video). Everything else passes unchanged. A
/// sequence split between two writes is held until it is whole.
pub struct SgrFilter<W: Write> {
    inner: W,
    depth: ColorDepth,
    /// An escape sequence begun and not yet ended.
    pending: Vec<u8>,
}

impl<W: Write> SgrFilter<W> {
    pub fn new(inner: W, depth: ColorDepth) -> Self {
        Self {
            inner,
            depth,
            pending: Vec::new(),
        }
    }

    pub fn depth(&self) -> ColorDepth {
        self.depth
    }

    pub fn get_ref(&self) -> &W {
        &self.inner
    }

    pub fn into_inner(self) -> W {
        self.inner
    }

    fn rewrites(&self) -> bool {
        matches!(self.depth, ColorDepth::None | ColorDepth::Ansi16)
    }

    /// Filters `buf` into `out`.
    fn filter(&mut self, buf: &[u8], out: &mut Vec<u8>) {
        for &b in buf {
            if self.pending.is_empty() {
                if b == 0x1b {
                    self.pending.push(b);
                } else {
                    out.push(b);
                }
                continue;
            }
            self.pending.push(b);
            let n = self.pending.len();
            if n == 2 && b == 0x1b {
                // a lone ESC, and another sequence begins
                out.push(0x1b);
                self.pending.remove(0);
            } else if n == 2 && b != b'[' {
                // not a CSI sequence
                out.append(&mut self.pending);
            } else if n > 2 && (0x40..=0x7e).contains(&b) {
                let seq = std::mem::take(&mut self.pending);
                if b == b'm' {
                    rewrite_sgr(&seq[2..n - 1], self.depth, out);
                } else {
                    out.extend_from_slice(&seq);
                }
            } else if n >= MAX_SEQ {
                out.append(&mut self.pending);
            }
        }
    }
}

impl<W: Write> Write for SgrFilter<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if !self.rewrites() {
            return self.inner.write(buf);
        }
        let mut out = Vec::with_capacity(buf.len());
        self.filter(buf, &mut out);
        self.inner.write_all(&out)?;
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// The nearest of the 16 colours (0–15) to an RGB colour.
fn nearest16(r: u8, g: u8, b: u8) -> u8 {
    const RGB16: [(i32, i32, i32); 16] = [
        (0, 0, 0),
        (205, 0, 0),
        (0, 205, 0),
        (205, 205, 0),
        (0, 0, 238),
        (205, 0, 205),
        (0, 205, 205),
        (229, 229, 229),
        (127, 127, 127),
        (255, 0, 0),
        (0, 255, 0),
        (255, 255, 0),
        (92, 92, 255),
        (255, 0, 255),
        (0, 255, 255),
        (255, 255, 255),
    ];
    let d = |&(cr, cg, cb): &(i32, i32, i32)| {
        let (dr, dg, db) = (cr - r as i32, cg - g as i32, cb - b as i32);
        dr * dr + dg * dg + db * db
    };
    (0..16u8)
        .min_by_key(|&i| d(&RGB16[i as usize]))
        .unwrap_or(7)
}

/// The 16-colour index of a 256-colour index.
fn index16(n: u8) -> u8 {
    match n {
        0..=15 => n,
        16..=231 => {
            let k = n - 16;
            let level = |c: u8| if c == 0 { 0 } else { 55 + 40 * c };
            nearest16(level(k / 36), level((k / 6) % 6), level(k % 6))
        }
        _ => {
            let v = 8 + 10 * (n - 232);
            nearest16(v, v, v)
        }
    }
}

/// The SGR parameters `params` (`38;5;9;1`) rewritten to `depth`, as a whole sequence into
/// `out` (nothing when every parameter was a colour dropped).
fn rewrite_sgr(params: &[u8], depth: ColorDepth, out: &mut Vec<u8>) {
    let text = String::from_utf8_lossy(params);
    if text.is_empty() {
        // ESC[m: reset
        out.extend_from_slice(b"\x1b[m");
        return;
    }
    let p: Vec<&str> = text.split(';').collect();
    let num = |i: usize| p.get(i).and_then(|s| s.parse::<u16>().ok());
    let mut kept: Vec<String> = Vec::new();
    let mut i = 0;
    while i < p.len() {
        let Some(v) = num(i) else {
            // `38:5:9` and the like: dropped; other forms with colons kept
            let extended = ["38:", "48:", "58:"].iter().any(|x| p[i].starts_with(x));
            if !extended {
                kept.push(p[i].to_string());
            }
            i += 1;
            continue;
        };
        // an extended colour: 38/48/58 ; 5 ; n  or  38/48/58 ; 2 ; r ; g ; b
        if matches!(v, 38 | 48 | 58) {
            let (index, used) = match num(i + 1) {
                Some(5) => (num(i + 2).map(|n| index16(n.min(255) as u8)), 3),
                Some(2) => {
                    let c = |k| num(i + k).unwrap_or(0).min(255) as u8;
                    (Some(nearest16(c(2), c(3), c(4))), 5)
                }
                _ => (None, 1),
            };
            if let (Some(n), ColorDepth::Ansi16, 38 | 48) = (index, depth, v) {
                let base = match (v, n < 8) {
                    (38, true) => 30,
                    (38, false) => 90 - 8,
                    (_, true) => 40,
                    (_, false) => 100 - 8,
                };
                kept.push((base + n as u16).to_string());
            }
            i += used;
            continue;
        }
        let colour = matches!(v, 30..=37 | 39 | 40..=47 | 49 | 59 | 90..=97 | 100..=107);
        if !(colour && depth == ColorDepth::None) {
            kept.push(p[i].to_string());
        }
        i += 1;
    }
    if kept.is_empty() {
        return;
    }
    out.extend_from_slice(b"\x1b[");
    out.extend_from_slice(kept.join(";").as_bytes());
    out.push(b'm');
}

#[cfg(test)]
mod tests {
    use super::*;

    fn through(depth: ColorDepth, input: &[u8]) -> Vec<u8> {
        let mut f = SgrFilter::new(Vec::new(), depth);
        f.write_all(input).unwrap();
        f.into_inner()
    }

    #[test]
    fn indexed_colours_become_the_16_colour_codes() {
        let d = ColorDepth::Ansi16;
        assert_eq!(through(d, b"\x1b[38;5;9mX"), b"\x1b[91mX");
        assert_eq!(through(d, b"\x1b[38;5;1m"), b"\x1b[31m");
        assert_eq!(through(d, b"\x1b[48;5;14m"), b"\x1b[106m");
        assert_eq!(through(d, b"\x1b[48;5;4m"), b"\x1b[44m");
        assert_eq!(through(d, b"\x1b[1;38;5;11;7m"), b"\x1b[1;93;7m");
        // RGB and the 256-colour cube: the nearest of the 16
        assert_eq!(through(d, b"\x1b[38;2;250;10;10m"), b"\x1b[91m");
        assert_eq!(through(d, b"\x1b[38;5;196m"), b"\x1b[91m");
        assert_eq!(through(d, b"\x1b[48;5;232m"), b"\x1b[40m");
        // underline colour dropped, the sequence with it
        assert_eq!(through(d, b"\x1b[58;5;3m"), b"");
        // other sequences pass unchanged
        let other = b"\x1b[2J\x1b[5;10H\x1b[?25l\x1b[0m\x1b[m\x1b7abc";
        assert_eq!(through(d, other), other);
    }

    #[test]
    fn without_colour_every_colour_is_dropped_and_the_rest_kept() {
        let d = ColorDepth::None;
        assert_eq!(through(d, b"\x1b[38;5;9mX\x1b[39m"), b"X");
        assert_eq!(through(d, b"\x1b[1;31;7m"), b"\x1b[1;7m");
        assert_eq!(through(d, b"\x1b[0m\x1b[m"), b"\x1b[0m\x1b[m");
    }

    #[test]
    fn a_sequence_split_between_writes_is_rewritten_whole() {
        let input = b"ab\x1b[1;38;5;12mcd\x1b[48;5;3m\x1b[Hef";
        let whole = through(ColorDepth::Ansi16, input);
        assert_eq!(whole, b"ab\x1b[1;94mcd\x1b[43m\x1b[Hef");
        let mut f = SgrFilter::new(Vec::new(), ColorDepth::Ansi16);
        for b in input {
            f.write_all(std::slice::from_ref(b)).unwrap();
        }
        assert_eq!(f.into_inner(), whole);
    }

    #[test]
    fn the_depth_comes_from_no_color_term_and_colorterm() {
        let of = |vars: &[(&str, &str)]| {
            let vars: Vec<(String, String)> = vars
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            ColorDepth::from_vars(&|k| vars.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()))
        };
        assert_eq!(of(&[("TERM", "vt100")]), ColorDepth::Ansi16);
        assert_eq!(of(&[("TERM", "linux")]), ColorDepth::Ansi16);
        assert_eq!(of(&[("TERM", "xterm")]), ColorDepth::Ansi16);
        assert_eq!(of(&[("TERM", "screen")]), ColorDepth::Ansi16);
        assert_eq!(of(&[]), ColorDepth::Ansi16);
        assert_eq!(of(&[("TERM", "dumb")]), ColorDepth::None);
        assert_eq!(of(&[("TERM", "xterm-256color")]), ColorDepth::Ansi256);
        assert_eq!(of(&[("TERM", "tmux-256color")]), ColorDepth::Ansi256);
        let truecolor = [("TERM", "xterm-256color"), ("COLORTERM", "truecolor")];
        assert_eq!(of(&truecolor), ColorDepth::TrueColor);
        assert_eq!(of(&[("COLORTERM", "24bit")]), ColorDepth::TrueColor);
        assert_eq!(of(&[("TERM", "xterm-direct")]), ColorDepth::TrueColor);
        let no_color = [("TERM", "xterm-256color"), ("NO_COLOR", "1")];
        assert_eq!(of(&no_color), ColorDepth::None);
        // an empty NO_COLOR is not set
        let empty = [("TERM", "xterm-256color"), ("NO_COLOR", "")];
        assert_eq!(of(&empty), ColorDepth::Ansi256);
    }

    #[test]
    fn the_glyphs_come_from_term_unless_overridden() {
        let of = |vars: &[(&str, &str)]| {
            let vars: Vec<(String, String)> = vars
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            Glyphs::from_vars(&|k| vars.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()))
        };
        for term in [
            "dumb", "linux", "vt100", "vt102", "vt220", "vt52", "vt100-am", "ansi", "VT220",
        ] {
            assert_eq!(of(&[("TERM", term)]), Ok(Glyphs::Ascii), "{term}");
        }
        for term in [
            "xterm-256color",
            "xterm",
            "screen",
            "screen.xterm-256color",
            "tmux-256color",
            "rxvt-unicode",
            "alacritty",
            "xterm-kitty",
            "foot",
            "",
        ] {
            assert_eq!(of(&[("TERM", term)]), Ok(Glyphs::Unicode), "{term}");
        }
        assert_eq!(of(&[]), Ok(Glyphs::Unicode));
        // NO_COLOR takes the colour away, not the glyphs
        let no_color = [("TERM", "xterm-256color"), ("NO_COLOR", "1")];
        assert_eq!(of(&no_color), Ok(Glyphs::Unicode));
        // the override wins over TERM, either way
        let forced = [("TERM", "vt100"), (GLYPHS_VAR, "unicode")];
        assert_eq!(of(&forced), Ok(Glyphs::Unicode));
        let forced = [("TERM", "xterm-256color"), (GLYPHS_VAR, "ASCII")];
        assert_eq!(of(&forced), Ok(Glyphs::Ascii));
        let forced = [("TERM", "xterm-256color"), ("DECKSPIN_ASCII", "1")];
        assert_eq!(of(&forced), Ok(Glyphs::Ascii));
        let both = [
            ("TERM", "linux"),
            ("DECKSPIN_ASCII", "1"),
            (GLYPHS_VAR, "unicode"),
        ];
        assert_eq!(of(&both), Ok(Glyphs::Unicode));
        // DECKSPIN_ASCII=0 and an empty override change nothing
        let off = [("TERM", "xterm"), ("DECKSPIN_ASCII", "0"), (GLYPHS_VAR, "")];
        assert_eq!(of(&off), Ok(Glyphs::Unicode));
        // an unknown value is an error naming the variable and the value
        let bad = of(&[("TERM", "xterm"), (GLYPHS_VAR, "braille")]);
        assert_eq!(
            bad,
            Err("DECKSPIN_GLYPHS='braille': expected ascii or unicode".into())
        );
        assert_eq!(Glyphs::parse(" Unicode "), Some(Glyphs::Unicode));
        assert_eq!(Glyphs::parse("utf8"), None);
    }
}
