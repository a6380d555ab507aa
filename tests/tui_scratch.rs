use deckspin::tui::{self, App, update, Msg};
use ratatui::{Terminal, backend::TestBackend};
use std::path::Path;

fn fixture() -> App {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    let text = text.replace("t_end = 16.0", "t_end = 2.0").replace("gaps = [0.0127, 0.0127, 0.0127, 0.0127]", "gaps = [0.004, 0.004, 0.004, 0.004]");
    let mut app = App::new_from_text(&text, &p);
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    app
}

#[test]
fn show() {
    let mut app = fixture();
    for (w, h) in [(120u16, 40u16), (80, 24), (60, 18)] {
        update(&mut app, Msg::Resize(w, h));
        let mut t = Terminal::new(TestBackend::new(w, h)).unwrap();
        t.draw(|f| tui::ui::draw(f, &app)).unwrap();
        println!("{}", t.backend());
    }
    update(&mut app, Msg::Action(tui::keymap::Action::SwitchView));
    let mut t = Terminal::new(TestBackend::new(120, 40)).unwrap();
    t.draw(|f| tui::ui::draw(f, &app)).unwrap();
    println!("{}", t.backend());
}
