//! One plotting module: charts as data (`chart`: series, axes with titles, units and linear or
//! log scales, bands, markers, reference lines, horizontal bars on labelled rows; grids of
//! categorical cells), round ticks (`ticks`), and two renderers: SVG files for reports (`svg`)
//! and plain ASCII text for the terminal (`text`). No system library, font or crate is needed to draw.

pub mod chart;
pub mod svg;
pub mod text;
pub mod ticks;

pub use chart::{
    Axis, Band, Bars, Category, Cell, Chart, Grid, GridRow, Marker, PALETTE, RefLine, Scale,
    Series, Stroke,
};
