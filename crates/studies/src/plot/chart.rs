//! Charts as data: series of points with labels, axes with titles, units and scales, bands,
//! markers, dashed reference lines, horizontal bars on labelled rows; and grids of categorical
//! cells. The renderers
//! (`plot::svg`, `plot::text`) draw them; nothing here draws.

/// How an axis maps values to the page: v ↦ v (linear) or v ↦ log₁₀ v (values ≤ 0 are not
/// drawn).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

/// An axis: its title, unit, scale and (optionally) a fixed range.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub title: String,
    /// Shown in parentheses after the title; empty for a dimensionless quantity.
    pub unit: String,
    pub scale: Scale,
    /// Fixed (lo, hi); `None`: the data's extent widened to round ticks.
    pub range: Option<(f64, f64)>,
}

impl Axis {
    pub fn linear(title: &str, unit: &str) -> Self {
        Self {
            title: title.into(),
            unit: unit.into(),
            scale: Scale::Linear,
            range: None,
        }
    }

    pub fn log(title: &str, unit: &str) -> Self {
        Self {
            scale: Scale::Log,
            ..Self::linear(title, unit)
        }
    }

    pub fn with_range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }

    /// "title (unit)", or the title alone.
    pub fn label(&self) -> String {
        if self.unit.is_empty() {
            self.title.clone()
        } else {
            format!("{} ({})", self.title, self.unit)
        }
    }
}

/// The mark drawn at each point of a series.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    None,
    Circle,
    Square,
    Triangle,
    Cross,
}

/// How consecutive points of a series are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stroke {
    None,
    Solid,
    Dashed,
}

/// A labelled series of (x, y) points. A point that cannot be drawn (not finite, or ≤ 0 on a
/// log axis) breaks the line.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub stroke: Stroke,
    pub marker: Marker,
    /// Index into [`PALETTE`] (taken modulo its length).
    pub color: usize,
    /// The character of the text chart (an ASCII graphic character).
    pub glyph: char,
}

impl Series {
    /// A solid line without markers.
    pub fn line(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            stroke: Stroke::Solid,
            marker: Marker::None,
            color: 0,
            glyph: '*',
        }
    }

    /// Markers without a line.
    pub fn points(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self {
            stroke: Stroke::None,
            marker: Marker::Circle,
            ..Self::line(label, points)
        }
    }

    pub fn color(mut self, color: usize) -> Self {
        self.color = color;
        self
    }
    pub fn glyph(mut self, glyph: char) -> Self {
        self.glyph = glyph;
        self
    }
    pub fn marker(mut self, marker: Marker) -> Self {
        self.marker = marker;
        self
    }
    pub fn stroke(mut self, stroke: Stroke) -> Self {
        self.stroke = stroke;
        self
    }
}

/// A shaded band between two curves: (x, lo, hi) points in x order.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    pub label: String,
    pub points: Vec<(f64, f64, f64)>,
    pub color: usize,
}

/// A dashed line across the plot at x = `at` (vertical) or y = `at` (horizontal).
#[derive(Clone, Debug, PartialEq)]
pub struct RefLine {
    pub at: f64,
    pub vertical: bool,
    pub label: String,
    pub color: usize,
}

impl RefLine {
    pub fn vertical(at: f64, label: &str, color: usize) -> Self {
        Self {
            at,
            vertical: true,
            label: label.into(),
            color,
        }
    }
    pub fn horizontal(at: f64, label: &str, color: usize) -> Self {
        Self {
            vertical: false,
            ..Self::vertical(at, label, color)
        }
    }
}

/// Horizontal bars on the labelled rows of a chart ([`Chart::rows`]), each from one x to
/// another (a tornado chart's).
#[derive(Clone, Debug, PartialEq)]
pub struct Bars {
    pub label: String,
    /// (row, from, to): `row` an index into [`Chart::rows`] (0 at the top), `from` and `to`
    /// the x values of the bar's ends (either order).
    pub bars: Vec<(usize, f64, f64)>,
    pub color: usize,
    /// The character that fills the bar in the text chart (an ASCII graphic character).
    pub glyph: char,
}

/// An x–y chart: bands drawn first, then bars, then reference lines, then series in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub title: String,
    pub x: Axis,
    pub y: Axis,
    pub bands: Vec<Band>,
    pub lines: Vec<RefLine>,
    pub series: Vec<Series>,
    /// Labels of rows, top to bottom: when there are any, the y axis shows them instead of
    /// numbers, row i at y = n − i ([`Chart::row_y`]) on a span of 0.5 … n + 0.5.
    pub rows: Vec<String>,
    pub bars: Vec<Bars>,
}

impl Chart {
    pub fn new(title: &str, x: Axis, y: Axis) -> Self {
        Self {
            title: title.into(),
            x,
            y,
            bands: Vec::new(),
            lines: Vec::new(),
            series: Vec::new(),
            rows: Vec::new(),
            bars: Vec::new(),
        }
    }

    /// The y value of row `i` ([`Chart::rows`]): n − i, so that row 0 is at the top.
    pub fn row_y(&self, i: usize) -> f64 {
        self.rows.len() as f64 - i as f64
    }

    /// Every x value the chart draws (series, bands, bars, vertical lines).
    pub fn xs(&self) -> Vec<f64> {
        let mut v: Vec<f64> = (self.series.iter())
            .flat_map(|s| s.points.iter().map(|p| p.0))
            .collect();
        v.extend(self.bands.iter().flat_map(|b| b.points.iter().map(|p| p.0)));
        v.extend((self.bars.iter()).flat_map(|b| b.bars.iter().flat_map(|r| [r.1, r.2])));
        v.extend(self.lines.iter().filter(|l| l.vertical).map(|l| l.at));
        v
    }

    /// Every y value the chart draws (series, both edges of bands, horizontal lines; with
    /// rows, the span 0.5 … n + 0.5 of [`Chart::rows`]).
    pub fn ys(&self) -> Vec<f64> {
        let mut v: Vec<f64> = (self.series.iter())
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .collect();
        if !self.rows.is_empty() {
            v.extend([0.5, self.rows.len() as f64 + 0.5]);
        }
        v.extend((self.bands.iter()).flat_map(|b| b.points.iter().flat_map(|p| [p.1, p.2])));
        v.extend(self.lines.iter().filter(|l| !l.vertical).map(|l| l.at));
        v
    }
}

/// A category of grid cells: its name (legend), text-chart character and colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Category {
    pub name: String,
    pub glyph: char,
    pub color: usize,
}

/// One cell of a grid: its text and category (index into [`Grid::categories`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    pub label: String,
    pub category: usize,
}

/// A labelled row of cells.
#[derive(Clone, Debug, PartialEq)]
pub struct GridRow {
    pub label: String,
    pub cells: Vec<Cell>,
}

/// A grid of categorical cells (rows of different lengths allowed), e.g. method × knob →
/// ok / inaccurate / unstable.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub title: String,
    /// What the columns are ("knob, coarse to fine").
    pub columns: String,
    pub rows: Vec<GridRow>,
    pub categories: Vec<Category>,
}

/// Colours of series, bands and categories (Tableau 10): blue, orange, green, red, purple,
/// brown, pink, grey, olive, cyan.
pub const PALETTE: [&str; 10] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];

/// The colour of palette index `i` (modulo the palette's length).
pub fn color(i: usize) -> &'static str {
    PALETTE[i % PALETTE.len()]
}
