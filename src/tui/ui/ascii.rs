//! The last pass of a frame in ASCII mode: any cell still holding a character above 0x7E
//! (one the panels did not spell out) gets an ASCII stand-in, so that nothing but ASCII
//! reaches the terminal.

use ratatui::buffer::Buffer;

/// The ASCII stand-in of a cell's symbol: box drawing as `-`, `|` or `+`, Braille dots as `.`,
/// blocks and shades as `#`, a few common signs by their look, anything else `?`. An empty
/// symbol (the second cell of a wide character) becomes a space, as the stand-in is narrow.
pub fn ascii_symbol(sym: &str) -> char {
    let mut chars = sym.chars();
    let Some(c) = chars.next() else {
        return ' ';
    };
    if (c as u32) < 0x7f && chars.next().is_none() {
        return c;
    }
    match c as u32 {
        // box drawing: horizontal, vertical, diagonal, the rest corners and junctions
        0x2500 | 0x2501 | 0x2504 | 0x2505 | 0x2508 | 0x2509 | 0x254c | 0x254d | 0x2550 | 0x2574
        | 0x2576 | 0x2578 | 0x257a | 0x257c | 0x257e => '-',
        0x2502 | 0x2503 | 0x2506 | 0x2507 | 0x250a | 0x250b | 0x254e | 0x254f | 0x2551 | 0x2575
        | 0x2577 | 0x2579 | 0x257b | 0x257d | 0x257f => '|',
        0x2571 => '/',
        0x2572 => '\\',
        0x2573 => 'X',
        0x2500..=0x257f => '+',
        // blocks and shades; the empty Braille pattern, then the others
        0x2580..=0x259f | 0x25a0 | 0x25ae => '#',
        0x2800 => ' ',
        0x2801..=0x28ff => '.',
        _ => match c {
            '•' | '●' | '·' | '∙' => '*',
            '…' => '.',
            '–' | '—' | '−' => '-',
            '×' => 'x',
            '→' | '▶' | '►' => '>',
            '←' | '◀' | '◄' => '<',
            '↑' | '▲' => '^',
            '↓' | '▼' => 'v',
            '‘' | '’' => '\'',
            '“' | '”' => '"',
            '\u{a0}' => ' ',
            _ => '?',
        },
    }
}

/// Replaces every cell symbol above 0x7E in `buf` by its [`ascii_symbol`].
pub fn ascii_only(buf: &mut Buffer) {
    let area = buf.area;
    for y in area.top()..area.bottom() {
        for x in area.left()..area.right() {
            let Some(cell) = buf.cell_mut((x, y)) else {
                continue;
            };
            let sym = cell.symbol();
            if !sym.is_ascii() || sym.is_empty() || sym.len() > 1 {
                let c = ascii_symbol(sym);
                cell.set_char(c);
            }
        }
    }
}
