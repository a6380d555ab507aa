//! The plotting module's renderers: the SVG parses back as XML and puts known points at the
//! pixels the layout gives; ticks fall at round numbers; the ASCII chart of a known line has
//! its characters in the expected cells.

use deckspin::plot::svg::{self, Area};
use deckspin::plot::text;
use deckspin::plot::ticks::span;
use deckspin::plot::{
    Axis, Band, Bars, Category, Cell, Chart, Grid, GridRow, Marker, RefLine, Series, Stroke,
};

fn parse(svg: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("not well-formed: {e}\n{svg}"))
}

fn num(n: &roxmltree::Node, a: &str) -> f64 {
    n.attribute(a).unwrap().parse().unwrap()
}

/// A chart using every element: band, both reference lines, every marker and stroke, and
/// text that must be escaped.
fn busy_chart() -> Chart {
    let mut c = Chart::new(
        "a <chart> & \"its\" θ",
        Axis::log("CPU time", "s"),
        Axis::linear("error", "%"),
    );
    c.bands.push(Band {
        label: "5–95 % band".into(),
        points: vec![(0.1, 1.0, 3.0), (1.0, 2.0, 4.0), (10.0, 2.5, 6.0)],
        color: 1,
    });
    c.lines.push(RefLine::horizontal(1.0, "1 % line", 3));
    c.lines.push(RefLine::vertical(2.0, "θ = 2 s", 2));
    let markers = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
        Marker::None,
    ];
    for (i, m) in markers.into_iter().enumerate() {
        let pts = vec![
            (0.1, i as f64),
            (1.0, i as f64 + 0.5),
            (-1.0, 2.0),
            (10.0, 5.0),
            (20.0, 6.0),
        ];
        let stroke = if i % 2 == 0 {
            Stroke::Solid
        } else {
            Stroke::Dashed
        };
        c.series.push(
            Series::line(&format!("s{i} <{i}>"), pts)
                .marker(m)
                .stroke(stroke)
                .color(i),
        );
    }
    c
}

#[test]
fn svg_is_well_formed_and_keeps_its_text() {
    let doc_text = svg::render(&busy_chart(), 640.0, 400.0);
    let doc = parse(&doc_text);
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(num(&root, "width"), 640.0);
    let title = (doc.descendants())
        .find(|n| n.attribute("class") == Some("title"))
        .unwrap();
    assert_eq!(title.text(), Some("a <chart> & \"its\" θ"));
    let x_title = (doc.descendants())
        .find(|n| n.attribute("class") == Some("x-title"))
        .unwrap();
    assert_eq!(x_title.text(), Some("CPU time (s)"));
    // the point at x = −1 cannot be drawn on the log axis: each line breaks there
    let lines = (doc.descendants())
        .filter(|n| n.attribute("class") == Some("series"))
        .count();
    assert_eq!(lines, 2 * 5);
    // legend: 5 series, 1 band, 2 reference lines
    let legend = (doc.descendants())
        .find(|n| n.attribute("class") == Some("legend"))
        .unwrap();
    let labels: Vec<&str> = (legend.descendants())
        .filter(|n| n.tag_name().name() == "text")
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(labels.len(), 8);
    assert_eq!(labels[0], "s0 <0>");
    assert_eq!(labels[7], "θ = 2 s");
}

#[test]
fn svg_points_land_at_their_pixels() {
    let mut c = Chart::new(
        "t",
        Axis::linear("x", "m").with_range(0.0, 10.0),
        Axis::linear("y", "").with_range(0.0, 1.0),
    );
    let pts = vec![(0.0, 0.0), (2.5, 0.25), (5.0, 0.5), (10.0, 1.0), (7.0, 0.1)];
    c.series
        .push(Series::points("abc", pts.clone()).marker(Marker::Circle));
    // legend of one 3-character label: right margin 44 + 7·3 = 65 px
    let area = svg::plot_area(&c, 640.0, 400.0);
    assert_eq!(
        area,
        Area {
            left: 72.0,
            top: 36.0,
            width: 640.0 - 72.0 - 65.0,
            height: 400.0 - 36.0 - 52.0,
        }
    );
    let text = svg::render(&c, 640.0, 400.0);
    let doc = parse(&text);
    let markers = (doc.descendants())
        .find(|n| n.attribute("class") == Some("markers"))
        .unwrap();
    let circles: Vec<(f64, f64)> = (markers.children())
        .filter(|n| n.tag_name().name() == "circle")
        .map(|n| (num(&n, "cx"), num(&n, "cy")))
        .collect();
    assert_eq!(circles.len(), pts.len());
    for ((x, y), (cx, cy)) in pts.iter().zip(&circles) {
        assert!((cx - (72.0 + 503.0 * x / 10.0)).abs() < 0.006, "{x} → {cx}");
        assert!(
            (cy - (36.0 + 312.0 * (1.0 - y))).abs() < 0.006,
            "{y} → {cy}"
        );
    }
    // x ticks every 2 m, labelled at their pixels
    let axes = (doc.descendants())
        .find(|n| n.attribute("class") == Some("axes"))
        .unwrap();
    let xt: Vec<(String, f64)> = (axes.children())
        .filter(|n| n.tag_name().name() == "text" && n.attribute("text-anchor") == Some("middle"))
        .filter(|n| n.attribute("class").is_none())
        .map(|n| (n.text().unwrap().to_string(), num(&n, "x")))
        .collect();
    let want: Vec<(String, f64)> = (0..=5)
        .map(|k| ((2 * k).to_string(), 72.0 + 503.0 * (2 * k) as f64 / 10.0))
        .collect();
    assert_eq!(xt.len(), want.len(), "{xt:?}");
    for ((a, pa), (b, pb)) in xt.iter().zip(&want) {
        assert_eq!(a, b);
        assert!((pa - pb).abs() < 0.006);
    }
}

#[test]
fn svg_log_axis_puts_decades_at_equal_steps() {
    let mut c = Chart::new(
        "t",
        Axis::log("x", "s").with_range(1.0, 1000.0),
        Axis::log("y", "").with_range(1e-4, 1.0),
    );
    c.series
        .push(Series::line("", vec![(10.0, 1e-2), (100.0, 1e-3)]));
    let a = svg::plot_area(&c, 500.0, 300.0);
    // no legend: right margin 24 px
    assert_eq!(a.width, 500.0 - 72.0 - 24.0);
    let doc_text = svg::render(&c, 500.0, 300.0);
    let doc = parse(&doc_text);
    let line = (doc.descendants())
        .find(|n| n.attribute("class") == Some("series"))
        .unwrap();
    let pts: Vec<f64> = (line.attribute("points").unwrap())
        .split([' ', ','])
        .map(|s| s.parse().unwrap())
        .collect();
    let want = [
        72.0 + a.width / 3.0,
        36.0 + a.height * 0.5,
        72.0 + a.width * 2.0 / 3.0,
        36.0 + a.height * 0.75,
    ];
    for (p, w) in pts.iter().zip(want) {
        assert!((p - w).abs() < 0.006, "{pts:?} vs {want:?}");
    }
}

#[test]
fn ticks_fall_at_round_numbers() {
    let s = span(&Axis::linear("", ""), &[0.013, 0.87]);
    assert_eq!((s.lo, s.hi), (0.0, 1.0));
    let t = s.ticks();
    assert_eq!(t, vec![0.0, 0.2, 0.4, 0.6, 0.8, 1.0]);
    let labels: Vec<String> = t.iter().map(|&v| s.label(v, &t)).collect();
    assert_eq!(labels, ["0", "0.2", "0.4", "0.6", "0.8", "1.0"]);

    let s = span(&Axis::linear("", ""), &[-37.0, 112.0]);
    assert_eq!((s.lo, s.hi), (-50.0, 150.0));
    assert_eq!(s.ticks(), vec![-50.0, 0.0, 50.0, 100.0, 150.0]);

    let s = span(&Axis::log("", ""), &[3e-4, 0.2, -1.0, f64::NAN]);
    assert_eq!((s.lo, s.hi), (1e-4, 1.0));
    let t = s.ticks();
    let labels: Vec<String> = t.iter().map(|&v| s.label(v, &t)).collect();
    assert_eq!(labels, ["1e-4", "0.001", "0.01", "0.1", "1"]);

    // inside one decade: 2 and 5 as well
    let s = span(&Axis::log("", ""), &[1.5, 8.0]);
    assert_eq!(s.ticks(), vec![1.0, 2.0, 5.0, 10.0]);
    // one value: widened around it
    let s = span(&Axis::linear("", ""), &[3.0]);
    assert!(s.lo < 3.0 && s.hi > 3.0);
}

#[test]
fn text_chart_of_a_known_line_puts_its_characters_where_expected() {
    let mut c = Chart::new(
        "y = x",
        Axis::linear("x", "m").with_range(0.0, 10.0),
        Axis::linear("y", "m").with_range(0.0, 10.0),
    );
    c.series
        .push(Series::line("", vec![(0.0, 0.0), (10.0, 10.0)]).glyph('#'));
    // y labels "0" … "10": gutter 2; 44 − 3 = 41 columns; 46 − 5 (no legend) = 41 rows
    let l = text::layout(&c, 44, 46);
    assert_eq!((l.gutter, l.cols, l.rows, l.top), (2, 41, 41, 2));
    let out = text::render(&c, 44, 46);
    assert!(out.is_ascii());
    let lines: Vec<&str> = out.lines().collect();
    let cell = |r: usize, k: usize| {
        lines[l.top + r]
            .chars()
            .nth(l.gutter + 1 + k)
            .unwrap_or(' ')
    };
    for k in 0..41 {
        for r in 0..41 {
            let want = if r == 40 - k { '#' } else { ' ' };
            assert_eq!(cell(r, k), want, "column {k}, row {r}:\n{out}");
        }
    }
    assert_eq!(lines[l.top], "10|                                        #");
    assert!(lines[l.top + 40].starts_with(" 0|#"));
    // the x axis: '+' at the corner and at every 2 m (every 8 columns)
    let axis = lines[l.top + 41];
    assert_eq!(&axis[..3], "  +");
    for k in 0..41 {
        let want = if k % 8 == 0 { '+' } else { '-' };
        assert_eq!(axis.chars().nth(3 + k), Some(want), "{axis}");
    }
    assert_eq!(
        lines[l.top + 42].trim_start(),
        "0       2       4       6       8      10"
    );
    assert_eq!(lines[0], "y = x");
    assert_eq!(lines[1], "y (m)");
}

#[test]
fn text_chart_draws_bands_lines_and_legend_in_ascii() {
    let mut c = Chart::new(
        "P(θ ≥ x) – band",
        Axis::linear("x", "g").with_range(0.0, 10.0),
        Axis::linear("P", "").with_range(0.0, 10.0),
    );
    c.bands.push(Band {
        label: "band".into(),
        points: vec![(0.0, 2.0, 4.0), (10.0, 2.0, 4.0)],
        color: 0,
    });
    c.lines.push(RefLine::vertical(5.0, "x = 5 μ", 1));
    c.series
        .push(Series::points("data", vec![(2.5, 7.5)]).glyph('o'));
    let l = text::layout(&c, 44, 49);
    assert_eq!((l.cols, l.rows), (41, 41));
    let out = text::render(&c, 44, 49);
    assert!(out.is_ascii(), "{out}");
    let lines: Vec<&str> = out.lines().collect();
    let cell = |r: usize, k: usize| {
        lines[l.top + r]
            .chars()
            .nth(l.gutter + 1 + k)
            .unwrap_or(' ')
    };
    // band rows 40 − 4·(4..2) = 24..=32 in every column but the reference line's
    for r in 0..41 {
        let want = if (24..=32).contains(&r) { '.' } else { ' ' };
        assert_eq!(cell(r, 3), want, "row {r}\n{out}");
    }
    for r in 0..41 {
        assert_eq!(cell(r, 20), ':', "row {r}\n{out}");
    }
    assert_eq!(cell(10, 10), 'o');
    assert_eq!(lines[0], "P(theta >= x) - band");
    assert!(out.contains("  o data\n  . band\n  : x = 5 mu\n"), "{out}");
}

#[test]
fn grids_render_their_categories() {
    let grid = Grid {
        title: "stability".into(),
        columns: "knob, coarse to fine".into(),
        rows: vec![
            GridRow {
                label: "event".into(),
                cells: vec![
                    Cell {
                        label: "rtol=1e-3".into(),
                        category: 0,
                    },
                    Cell {
                        label: "rtol=1e-5".into(),
                        category: 1,
                    },
                ],
            },
            GridRow {
                label: "moreau".into(),
                cells: vec![Cell {
                    label: "h=<1e-3>".into(),
                    category: 2,
                }],
            },
        ],
        categories: vec![
            Category {
                name: "ok".into(),
                glyph: 'o',
                color: 2,
            },
            Category {
                name: "inaccurate".into(),
                glyph: 'i',
                color: 1,
            },
            Category {
                name: "unstable".into(),
                glyph: 'U',
                color: 3,
            },
        ],
    };
    let s = svg::render_grid(&grid);
    let doc = parse(&s);
    let cells: Vec<&str> = (doc.descendants())
        .filter(|n| n.attribute("class") == Some("cell"))
        .map(|n| n.attribute("fill").unwrap())
        .collect();
    assert_eq!(cells, ["#2ca02c", "#ff7f0e", "#d62728"]);
    assert!(doc.descendants().any(|n| n.text() == Some("h=<1e-3>")));
    let t = text::render_grid(&grid, 80);
    assert!(t.is_ascii());
    let lines: Vec<&str> = t.lines().collect();
    assert_eq!(lines[2], "         1  2");
    assert_eq!(lines[3], "event    o  i");
    assert_eq!(lines[4], "moreau   U");
    assert_eq!(lines[5], "  o ok   i inaccurate   U unstable");
}

/// A chart of two labelled rows with bars from 2 to 6 and from 5 to 3 (x 0 … 10) and a
/// reference line at 5.
fn bar_chart() -> Chart {
    let mut c = Chart::new(
        "bars",
        Axis::linear("v", "m").with_range(0.0, 10.0),
        Axis::linear("", ""),
    );
    c.rows = vec!["first <a>".into(), "second".into()];
    c.bars.push(Bars {
        label: "low".into(),
        bars: vec![(0, 2.0, 6.0), (1, 5.0, 3.0)],
        color: 0,
        glyph: '=',
    });
    c.lines.push(RefLine::vertical(5.0, "base", 7));
    c
}

#[test]
fn bars_sit_on_their_rows_in_both_renderers() {
    let c = bar_chart();
    // rows at y = 2 (top) and 1 on a span of 0.5 … 2.5
    assert_eq!((c.row_y(0), c.row_y(1)), (2.0, 1.0));
    let a = svg::plot_area(&c, 640.0, 400.0);
    // the longest row label (9 characters) widens the left margin past 72 px: 36 + 1.1·7·9
    assert!((a.left - (36.0 + 1.1 * 7.0 * 9.0)).abs() < 1e-9, "{a:?}");
    let doc_text = svg::render(&c, 640.0, 400.0);
    let doc = parse(&doc_text);
    let rects: Vec<(f64, f64, f64, f64)> = (doc.descendants())
        .filter(|n| n.attribute("class") == Some("bar"))
        .map(|n| {
            (
                num(&n, "x"),
                num(&n, "y"),
                num(&n, "width"),
                num(&n, "height"),
            )
        })
        .collect();
    assert_eq!(rects.len(), 2);
    let px = |v: f64| a.left + a.width * v / 10.0;
    let py = |y: f64| a.top + a.height * (1.0 - (y - 0.5) / 2.0);
    // 0.6 of a row's height (a.height / 2) around the row's y
    let h = 0.6 * a.height / 2.0;
    for ((x, y, w, hh), (from, to, row)) in rects.iter().zip([(2.0, 6.0, 2.0), (3.0, 5.0, 1.0)]) {
        assert!((x - px(from)).abs() < 0.006 && (w - (px(to) - px(from))).abs() < 0.012);
        assert!((y - (py(row) - h / 2.0)).abs() < 0.006 && (hh - h).abs() < 0.012);
    }
    // the y axis shows the rows' labels at their rows instead of numbers
    let axes = (doc.descendants())
        .find(|n| n.attribute("class") == Some("axes"))
        .unwrap();
    let yl: Vec<(String, f64)> = (axes.children())
        .filter(|n| n.attribute("text-anchor") == Some("end"))
        .map(|n| (n.text().unwrap().to_string(), num(&n, "y")))
        .collect();
    assert_eq!(yl.len(), 2);
    assert_eq!(yl[0].0, "first <a>");
    assert!((yl[0].1 - (py(2.0) + 4.0)).abs() < 0.006);
    assert_eq!(yl[1].0, "second");
    // the bars in the legend
    let legend = (doc.descendants())
        .find(|n| n.attribute("class") == Some("legend"))
        .unwrap();
    let labels: Vec<&str> = (legend.descendants())
        .filter(|n| n.tag_name().name() == "text")
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(labels, ["low", "base"]);

    // text: each row's label in the gutter, its bar's columns filled, the line at 5 over them
    let t = text::render(&c, 60, 12);
    let l = text::layout(&c, 60, 12);
    assert_eq!(l.gutter, "first <a>".len());
    let lines: Vec<&str> = t.lines().collect();
    let col = |v: f64| (v / 10.0 * (l.cols - 1) as f64).round() as usize;
    let row = |y: f64| l.top + ((1.0 - (y - 0.5) / 2.0) * (l.rows - 1) as f64).round() as usize;
    for (r, label, from, to) in [(2.0, "first <a>", 2.0, 6.0), (1.0, "second", 3.0, 5.0)] {
        let line: Vec<char> = lines[row(r)].chars().collect();
        let text: String = line[..l.gutter].iter().collect();
        assert_eq!(text.trim(), label, "{t}");
        for k in col(from)..=col(to) {
            let want = if k == col(5.0) { ':' } else { '=' };
            assert_eq!(line[l.gutter + 1 + k], want, "column {k} of\n{t}");
        }
        assert_eq!(line.get(l.gutter + 1 + col(from) - 1), Some(&' '));
    }
    assert!(t.contains("  = low") && t.contains("  : base"), "{t}");
}
