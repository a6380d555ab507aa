//! The longest wall time between two observer batches of a run: a cancel (the workbench's
//! `Esc`) takes effect at the next batch, so this bounds its delay.
//!
//!     cargo run --release --example batch_latency -- MODEL [key=value …]

use deckspin::output::{EventRecord, Sample};
use std::time::Instant;

struct Watch {
    last: Instant,
    worst: f64,
    batches: usize,
}

impl deckspin::Observer for Watch {
    fn batch(&mut self, _: &[Sample], _: &[EventRecord], _: f64) -> bool {
        self.worst = self.worst.max(self.last.elapsed().as_secs_f64());
        self.last = Instant::now();
        self.batches += 1;
        true
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(model) = args.first() else {
        return Err("usage: batch_latency MODEL [key=value …]".into());
    };
    let scene = deckspin::load(std::path::Path::new(model), &args[1..])?;
    let mut w = Watch {
        last: Instant::now(),
        worst: 0.0,
        batches: 0,
    };
    let t0 = Instant::now();
    let run = deckspin::simulate::integrate(&scene, &mut w);
    println!(
        "{}: {} batches in {:.2} s, longest interval {:.1} ms",
        run.stop.label(),
        w.batches,
        t0.elapsed().as_secs_f64(),
        w.worst * 1e3
    );
    Ok(())
}
