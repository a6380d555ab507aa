//! The one keymap table: (context, keys, action, description). The key handler, the help
//! screen and the key-hint bar are all generated from [`KEYMAP`].

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// What a key does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Action {
    Quit,
    Help,
    SwitchView,
    SwitchViewBack,
    Rerun,
    Cancel,
    Save,
    Export,
    ToggleMarker,
    ToggleOverlay,
    CursorLeft,
    CursorRight,
    CursorLeftFast,
    CursorRightFast,
    CursorHome,
    CursorEnd,
    ZoomIn,
    ZoomOut,
    ZoomReset,
    NextElement,
    PrevElement,
    FieldUp,
    FieldDown,
    FieldPageUp,
    FieldPageDown,
    FieldEdit,
    FieldRevert,
    ItemDuplicate,
    ItemRemove,
    EditCommit,
    EditCancel,
    EditBackspace,
    EditClear,
    Yes,
    No,
    KeepMine,
    TakeTheirs,
    /// The swap file's edits as the draft / kept in a recovery file / deleted.
    SwapRecover,
    SwapKeep,
    SwapDelete,
    KeepMineAll,
    TakeTheirsAll,
    CloseHelp,
    StudyPrev,
    StudyNext,
    StudyRun,
    StudyCancel,
    StudyReopen,
    /// The record suite with one pair more / fewer.
    StudyMore,
    StudyFewer,
    /// The study's cursor to the previous / next point of its table.
    StudyPointPrev,
    StudyPointNext,
    /// The ladder's selected variant applied to the form's model / taken back.
    StudyApply,
    StudyUndo,
    /// The tornado's next quantity.
    StudyQuantity,
    PickUp,
    PickDown,
    PickLoad,
    PickClose,
    // the run list
    /// Open the run list (or go back from it).
    RunsView,
    RunUp,
    RunDown,
    /// Overlay the selected run (and compare it) or take it off.
    RunOverlay,
    /// Pin the selected run as the baseline.
    RunBaseline,
    RunRename,
    RunsToCharts,
    /// Delete the selected run (asks first).
    RunDelete,
    /// A run's whole status: open, close.
    RunInfo,
    CloseRunInfo,
    NameCommit,
    NameCancel,
    NameBackspace,
    NameClear,
    // navigation: events and the event list
    NextEvent,
    PrevEvent,
    ToggleEvents,
    EventUp,
    EventDown,
    EventPageUp,
    EventPageDown,
    EventGo,
    // any terminal: help scrolling, suspend
    HelpDown,
    HelpUp,
    /// The message log: open, close.
    Messages,
    CloseMessages,
    HelpPageDown,
    HelpPageUp,
    HelpTop,
    HelpBottom,
    /// Ctrl-Z: give the terminal back to the shell until `fg`.
    Suspend,
    // the results pages of the studies view
    /// The previous / next contact, mode or record component.
    ResultUp,
    ResultDown,
    /// Work-precision: the chart or the stability grid.
    ResultGrid,
    // the form: first/last field, search, folds; the model file: save and quit, open another
    FieldFirst,
    FieldLast,
    SearchStart,
    SearchNext,
    SearchPrev,
    SearchKeep,
    SearchCancel,
    SearchBackspace,
    FoldToggle,
    FoldAll,
    SaveQuit,
    OpenModel,
    ModelUp,
    ModelDown,
    ModelOpen,
    ModelClose,
    // the time charts: focus, series, y axis, θ's unit
    FocusChart1,
    FocusChart2,
    FocusChart3,
    /// Open the list of series for the focused chart.
    PickSeries,
    YZoomIn,
    YZoomOut,
    LogScale,
    ThetaUnit,
    SeriesUp,
    SeriesDown,
    SeriesPageUp,
    SeriesPageDown,
    SeriesToggle,
    SeriesClose,
    SeriesBackspace,
    SeriesDefaults,
}

/// Where a binding applies. Lookup order: the mode's own context first, then the view, then
/// [`Ctx::Global`] (global keys are off while editing, confirming or reading the help).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ctx {
    Global,
    Charts,
    Form,
    Studies,
    Pick,
    Edit,
    Confirm,
    Merge,
    /// A swap file of unsaved edits found at the start.
    Recover,
    /// The message log.
    Messages,
    Help,
    Runs,
    Naming,
    /// The event list is open in the charts view.
    Events,
    // the form's search, the quit question, the list of models
    Search,
    Quit,
    OpenModel,
    /// Choosing the series of a time chart.
    ChartPick,
    /// A run's whole status.
    RunInfo,
}

impl Ctx {
    pub fn title(self) -> &'static str {
        match self {
            Ctx::Global => "everywhere",
            Ctx::Charts => "charts view",
            Ctx::Form => "form view",
            Ctx::Studies => "studies view",
            Ctx::Pick => "choosing a study CSV",
            Ctx::Edit => "editing a value",
            Ctx::Confirm => "answering a question",
            Ctx::Merge => "a value changed on disk and here",
            Ctx::Recover => "unsaved edits found in a swap file",
            Ctx::Messages => "the message log",
            Ctx::Help => "this help",
            Ctx::Runs => "run list",
            Ctx::Naming => "naming a run",
            Ctx::Events => "the event list",
            Ctx::Search => "searching the form",
            Ctx::Quit => "quitting with unsaved edits",
            Ctx::OpenModel => "choosing a model to open",
            Ctx::ChartPick => "choosing a chart's series",
            Ctx::RunInfo => "a run's info",
        }
    }
}

/// One key: a character (shift ignored), a control character, a special key, or a special key
/// with shift.
#[derive(Clone, Copy, Debug)]
pub enum K {
    Ch(char),
    Ctrl(char),
    Code(KeyCode),
    Shift(KeyCode),
}

impl K {
    /// The key event this key is (for lookups).
    pub fn event(&self) -> KeyEvent {
        match *self {
            K::Ch(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE),
            K::Ctrl(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL),
            K::Code(c) => KeyEvent::new(c, KeyModifiers::NONE),
            K::Shift(c) => KeyEvent::new(c, KeyModifiers::SHIFT),
        }
    }

    pub fn matches(&self, ev: &KeyEvent) -> bool {
        let ctrl = ev.modifiers.contains(KeyModifiers::CONTROL);
        let shift = ev.modifiers.contains(KeyModifiers::SHIFT);
        match *self {
            K::Ch(c) => ev.code == KeyCode::Char(c) && !ctrl,
            K::Ctrl(c) => ev.code == KeyCode::Char(c) && ctrl,
            K::Code(code) => ev.code == code && !shift && !ctrl,
            K::Shift(code) => ev.code == code && shift,
        }
    }
}

pub struct Binding {
    pub ctx: Ctx,
    pub keys: &'static [K],
    /// How the keys are written on screen.
    pub label: &'static str,
    pub action: Action,
    pub desc: &'static str,
    /// (keys, text) for the key-hint bar (None: help screen only).
    pub hint: Option<(&'static str, &'static str)>,
}

use Action as A;
use KeyCode as KC;

const fn b(
    ctx: Ctx,
    keys: &'static [K],
    label: &'static str,
    action: Action,
    desc: &'static str,
    hint: Option<(&'static str, &'static str)>,
) -> Binding {
    Binding {
        ctx,
        keys,
        label,
        action,
        desc,
        hint,
    }
}

/// The keymap. Order matters for the hint bar (most useful first).
#[rustfmt::skip]
pub const KEYMAP: &[Binding] = &[
    // editing a value
    b(Ctx::Edit, &[K::Code(KC::Enter)], "Enter", A::EditCommit, "accept (refused if invalid)", Some(("Enter", "accept"))),
    b(Ctx::Edit, &[K::Code(KC::Esc)], "Esc", A::EditCancel, "abandon the edit", Some(("Esc", "cancel"))),
    b(Ctx::Edit, &[K::Code(KC::Backspace)], "Bksp", A::EditBackspace, "delete a character", Some(("Bksp", "delete"))),
    b(Ctx::Edit, &[K::Ctrl('u')], "^U", A::EditClear, "clear the value", Some(("^U", "clear"))),
    // questions
    b(Ctx::Confirm, &[K::Ch('y')], "y", A::Yes, "yes", Some(("y", "yes"))),
    b(Ctx::Confirm, &[K::Ch('n'), K::Code(KC::Esc)], "n/Esc", A::No, "no", Some(("n/Esc", "no"))),
    // a value changed both on disk and in the workbench
    b(Ctx::Recover, &[K::Ch('r')], "r", A::SwapRecover, "recover the edits", Some(("r", "recover"))),
    b(Ctx::Recover, &[K::Ch('k'), K::Code(KC::Esc)], "k/Esc", A::SwapKeep, "keep them in a file", Some(("k/Esc", "keep as file"))),
    b(Ctx::Recover, &[K::Ch('d')], "d", A::SwapDelete, "delete them", Some(("d", "delete"))),
    b(Ctx::Merge, &[K::Ch('m')], "m", A::KeepMine, "keep my value", Some(("m", "keep mine"))),
    b(Ctx::Merge, &[K::Ch('t')], "t", A::TakeTheirs, "take the value on disk", Some(("t", "take theirs"))),
    b(Ctx::Merge, &[K::Ch('M')], "M", A::KeepMineAll, "keep mine for all of them", Some(("M", "mine for all"))),
    b(Ctx::Merge, &[K::Ch('T')], "T", A::TakeTheirsAll, "take theirs for all of them", Some(("T", "theirs for all"))),
    // choosing a study's CSV to reopen
    b(Ctx::Pick, &[K::Code(KC::Up), K::Ch('k')], "Up/k", A::PickUp, "previous file", None),
    b(Ctx::Pick, &[K::Code(KC::Down), K::Ch('j')], "Down/j", A::PickDown, "next file", Some(("j/k", "file"))),
    b(Ctx::Pick, &[K::Code(KC::Enter)], "Enter", A::PickLoad, "open the study of the file", Some(("Enter", "open"))),
    b(Ctx::Pick, &[K::Code(KC::Esc), K::Ch('q')], "Esc/q", A::PickClose, "close the list", Some(("Esc", "close"))),
    // help
    b(Ctx::Help, &[K::Ch('?'), K::Code(KC::Esc), K::Ch('q')], "?/Esc/q", A::CloseHelp, "close the help", Some(("?/Esc/q", "close"))),
    // charts view
    b(Ctx::Charts, &[K::Code(KC::Left), K::Ch('h')], "←/h", A::CursorLeft, "cursor left", Some(("←→", "cursor"))),
    b(Ctx::Charts, &[K::Code(KC::Right), K::Ch('l')], "→/l", A::CursorRight, "cursor right", None),
    b(Ctx::Charts, &[K::Shift(KC::Left), K::Ch('H')], "S-←/H", A::CursorLeftFast, "cursor left 10 %", None),
    b(Ctx::Charts, &[K::Shift(KC::Right), K::Ch('L')], "S-→/L", A::CursorRightFast, "cursor right 10 %", None),
    b(Ctx::Charts, &[K::Code(KC::Home)], "Home", A::CursorHome, "cursor to the start", None),
    b(Ctx::Charts, &[K::Code(KC::End)], "End", A::CursorEnd, "cursor to the end (follow)", None),
    b(Ctx::Charts, &[K::Ch('+'), K::Ch('=')], "+", A::ZoomIn, "zoom in around the cursor", Some(("+-", "zoom"))),
    b(Ctx::Charts, &[K::Ch('-')], "-", A::ZoomOut, "zoom out", None),
    b(Ctx::Charts, &[K::Ch('0')], "0", A::ZoomReset, "show the whole run", None),
    b(Ctx::Charts, &[K::Ch('n')], "n", A::NextElement, "next column (force–def.)", Some(("n", "column"))),
    b(Ctx::Charts, &[K::Ch('N')], "N", A::PrevElement, "previous column", None),
    // charts view: events
    b(Ctx::Charts, &[K::Ch(']')], "]", A::NextEvent, "cursor to the next event", None),
    b(Ctx::Charts, &[K::Ch('[')], "[", A::PrevEvent, "cursor to the previous event", None),
    b(Ctx::Charts, &[K::Ch('E')], "E", A::ToggleEvents, "event list: open/close", None),
    // charts view: the time charts' series, y axis and θ's unit
    b(Ctx::Charts, &[K::Ch('p')], "p", A::PickSeries, "pick the chart's series", Some(("p", "series"))),
    b(Ctx::Charts, &[K::Ch('1')], "1", A::FocusChart1, "focus the top chart", None),
    b(Ctx::Charts, &[K::Ch('2')], "2", A::FocusChart2, "focus the second chart", None),
    b(Ctx::Charts, &[K::Ch('3')], "3", A::FocusChart3, "focus the third chart", None),
    b(Ctx::Charts, &[K::Ch('Y')], "Y", A::YZoomIn, "y zoom in (focused chart)", None),
    b(Ctx::Charts, &[K::Ch('y')], "y", A::YZoomOut, "y zoom out", None),
    b(Ctx::Charts, &[K::Ch('g')], "g", A::LogScale, "log scale of |y| on/off", None),
    b(Ctx::Charts, &[K::Ch('d')], "d", A::ThetaUnit, "θ in rad, mrad or degrees", None),
    // choosing a chart's series
    b(Ctx::ChartPick, &[K::Code(KC::Up)], "↑", A::SeriesUp, "previous series", None),
    b(Ctx::ChartPick, &[K::Code(KC::Down)], "↓", A::SeriesDown, "next series", Some(("↑↓", "series"))),
    b(Ctx::ChartPick, &[K::Code(KC::PageUp)], "PgUp", A::SeriesPageUp, "a page of series up", None),
    b(Ctx::ChartPick, &[K::Code(KC::PageDown)], "PgDn", A::SeriesPageDown, "a page of series down", None),
    b(Ctx::ChartPick, &[K::Ch(' ')], "Space", A::SeriesToggle, "show or hide the series", Some(("Space", "show/hide"))),
    b(Ctx::ChartPick, &[K::Code(KC::Enter), K::Code(KC::Esc)], "Enter/Esc", A::SeriesClose, "close the list", Some(("Enter", "close"))),
    b(Ctx::ChartPick, &[K::Code(KC::Backspace)], "Bksp", A::SeriesBackspace, "delete a filter character", Some(("type", "filter"))),
    b(Ctx::ChartPick, &[K::Ctrl('d')], "^D", A::SeriesDefaults, "the chart's default series", None),
    // the event list
    b(Ctx::Events, &[K::Code(KC::Up), K::Ch('k')], "↑/k", A::EventUp, "previous event in the list", None),
    b(Ctx::Events, &[K::Code(KC::Down), K::Ch('j')], "↓/j", A::EventDown, "next event in the list", Some(("↑↓", "event"))),
    b(Ctx::Events, &[K::Code(KC::PageUp)], "PgUp", A::EventPageUp, "a page of events up", None),
    b(Ctx::Events, &[K::Code(KC::PageDown)], "PgDn", A::EventPageDown, "a page of events down", None),
    b(Ctx::Events, &[K::Code(KC::Enter)], "Enter", A::EventGo, "cursor to the selected event", Some(("Enter", "go"))),
    // form view
    b(Ctx::Form, &[K::Code(KC::Up), K::Ch('k')], "↑/k", A::FieldUp, "previous field", None),
    b(Ctx::Form, &[K::Code(KC::Down), K::Ch('j')], "↓/j", A::FieldDown, "next field", Some(("↑↓", "field"))),
    b(Ctx::Form, &[K::Code(KC::PageUp)], "PgUp", A::FieldPageUp, "page up", None),
    b(Ctx::Form, &[K::Code(KC::PageDown)], "PgDn", A::FieldPageDown, "page down", None),
    b(Ctx::Form, &[K::Code(KC::Enter)], "Enter", A::FieldEdit, "edit the value", Some(("Enter", "edit"))),
    b(Ctx::Form, &[K::Ch('u')], "u", A::FieldRevert, "revert field; undo a variant", Some(("u", "revert"))),
    b(Ctx::Form, &[K::Ch('+')], "+", A::ItemDuplicate, "copy frame/bent/run; add key", None),
    b(Ctx::Form, &[K::Ch('-')], "-", A::ItemRemove, "remove frame, bent, run, key", None),
    // studies view
    b(Ctx::Studies, &[K::Code(KC::Left), K::Ch('h')], "Left/h", A::StudyPrev, "previous study or results page", None),
    b(Ctx::Studies, &[K::Code(KC::Right), K::Ch('l')], "Right/l", A::StudyNext, "next study or results page", Some(("h/l", "study"))),
    b(Ctx::Studies, &[K::Code(KC::Enter)], "Enter", A::StudyRun, "run the study (form's model)", Some(("Enter", "run study"))),
    b(Ctx::Studies, &[K::Code(KC::Esc)], "Esc", A::StudyCancel, "cancel the running study", Some(("Esc", "cancel study"))),
    b(Ctx::Studies, &[K::Ch('f')], "f", A::StudyReopen, "reopen a study from its CSV", Some(("f", "reopen CSV"))),
    b(Ctx::Studies, &[K::Ch('+'), K::Ch('=')], "+", A::StudyMore, "suite: one record pair more", None),
    b(Ctx::Studies, &[K::Ch('-')], "-", A::StudyFewer, "suite: one record pair fewer", None),
    b(Ctx::Studies, &[K::Ch('[')], "[", A::StudyPointPrev, "cursor to the previous point", None),
    b(Ctx::Studies, &[K::Ch(']')], "]", A::StudyPointNext, "cursor to the next point", Some(("[ ]", "point"))),
    b(Ctx::Studies, &[K::Ch('a')], "a", A::StudyApply, "adequacy: apply the variant", None),
    b(Ctx::Studies, &[K::Ch('u')], "u", A::StudyUndo, "undo the variant applied", None),
    b(Ctx::Studies, &[K::Ch('n')], "n", A::StudyQuantity, "sensitivity: next quantity", None),
    // the run list
    b(Ctx::Runs, &[K::Code(KC::Up), K::Ch('k')], "Up/k", A::RunUp, "previous run", None),
    b(Ctx::Runs, &[K::Code(KC::Down), K::Ch('j')], "Down/j", A::RunDown, "next run", Some(("j/k", "run"))),
    b(Ctx::Runs, &[K::Ch(' ')], "Space", A::RunOverlay, "overlay and compare, or not", Some(("Space", "overlay"))),
    b(Ctx::Runs, &[K::Ch('b')], "b", A::RunBaseline, "pin the run as the baseline", Some(("b", "baseline"))),
    b(Ctx::Runs, &[K::Ch('n')], "n", A::RunRename, "name the run", Some(("n", "name"))),
    b(Ctx::Runs, &[K::Code(KC::Enter)], "Enter", A::RunsToCharts, "back to the charts", Some(("Enter", "charts"))),
    b(Ctx::Runs, &[K::Ch('i')], "i", A::RunInfo, "status, reason, method, step", Some(("i", "info"))),
    b(Ctx::Runs, &[K::Ch('d'), K::Code(KC::Delete)], "d/Del", A::RunDelete, "delete the run (asks first)", Some(("d", "delete"))),
    b(Ctx::Charts, &[K::Ch('i')], "i", A::RunInfo, "the shown run's whole status", None),
    // a run's info
    b(Ctx::RunInfo, &[K::Code(KC::Down), K::Ch('j')], "↓/j", A::HelpDown, "scroll down", Some(("j/k", "scroll"))),
    b(Ctx::RunInfo, &[K::Code(KC::Up), K::Ch('k')], "↑/k", A::HelpUp, "scroll up", None),
    b(Ctx::RunInfo, &[K::Code(KC::PageDown)], "PgDn", A::HelpPageDown, "page down", None),
    b(Ctx::RunInfo, &[K::Code(KC::PageUp)], "PgUp", A::HelpPageUp, "page up", None),
    b(Ctx::RunInfo, &[K::Code(KC::Home)], "Home", A::HelpTop, "to the top", None),
    b(Ctx::RunInfo, &[K::Code(KC::End)], "End", A::HelpBottom, "to the end", None),
    b(Ctx::RunInfo, &[K::Code(KC::Esc), K::Ch('q'), K::Ch('i')], "Esc/q/i", A::CloseRunInfo, "close the run info", Some(("Esc", "close"))),
    // naming a run
    b(Ctx::Naming, &[K::Code(KC::Enter)], "Enter", A::NameCommit, "keep it (empty: derived)", Some(("Enter", "keep"))),
    b(Ctx::Naming, &[K::Code(KC::Esc)], "Esc", A::NameCancel, "leave the name as it was", Some(("Esc", "cancel"))),
    b(Ctx::Naming, &[K::Code(KC::Backspace)], "Bksp", A::NameBackspace, "delete a character", Some(("Bksp", "delete"))),
    b(Ctx::Naming, &[K::Ctrl('u')], "^U", A::NameClear, "clear the name", Some(("^U", "clear"))),
    // the results pages of the studies view
    b(Ctx::Studies, &[K::Code(KC::Down), K::Ch('j')], "Down/j", A::ResultDown, "next contact/mode/record/row", Some(("j/k", "select"))),
    b(Ctx::Studies, &[K::Code(KC::Up), K::Ch('k')], "Up/k", A::ResultUp, "previous one", None),
    b(Ctx::Studies, &[K::Ch('g')], "g", A::ResultGrid, "precision: chart or grid", None),
    // everywhere
    b(Ctx::Global, &[K::Ch('q'), K::Ctrl('c')], "q", A::Quit, "quit (asks if edits unsaved)", Some(("q", "quit"))),
    b(Ctx::Global, &[K::Ch('?')], "?", A::Help, "this help", Some(("?", "help"))),
    b(Ctx::Global, &[K::Code(KC::Tab)], "Tab", A::SwitchView, "view: charts, form, studies", Some(("Tab", "view"))),
    b(Ctx::Global, &[K::Code(KC::BackTab), K::Shift(KC::BackTab)], "S-Tab", A::SwitchViewBack, "the view before", None),
    b(Ctx::Global, &[K::Ch('s')], "s", A::Save, "save the file and rerun", Some(("s", "save"))),
    b(Ctx::Global, &[K::Ch('r')], "r", A::Rerun, "rerun (with unsaved edits)", Some(("r", "rerun"))),
    b(Ctx::Global, &[K::Ch('#')], "#", A::RunsView, "list, pin and compare the runs", Some(("#", "runs"))),
    b(Ctx::Global, &[K::Code(KC::Esc), K::Ch('c')], "Esc/c", A::Cancel, "cancel the simulation", Some(("Esc", "cancel"))),
    b(Ctx::Global, &[K::Ch('e')], "e", A::Export, "export chart + events CSV", Some(("e", "export"))),
    b(Ctx::Global, &[K::Ch('o')], "o", A::ToggleOverlay, "show/hide the overlaid runs", Some(("o", "overlay"))),
    b(Ctx::Global, &[K::Ch('m')], "m", A::ToggleMarker, "ASCII mode on/off", Some(("m", "ASCII"))),
    // any terminal: help scrolling, suspend
    b(Ctx::Help, &[K::Code(KC::Down), K::Ch('j')], "↓/j", A::HelpDown, "scroll down", Some(("j/k", "scroll"))),
    b(Ctx::Help, &[K::Code(KC::Up), K::Ch('k')], "↑/k", A::HelpUp, "scroll up", None),
    b(Ctx::Help, &[K::Code(KC::PageDown)], "PgDn", A::HelpPageDown, "page down", Some(("PgDn", "page"))),
    b(Ctx::Help, &[K::Code(KC::PageUp)], "PgUp", A::HelpPageUp, "page up", None),
    b(Ctx::Help, &[K::Code(KC::Home)], "Home", A::HelpTop, "to the top", None),
    b(Ctx::Help, &[K::Code(KC::End)], "End", A::HelpBottom, "to the end", None),
    b(Ctx::Global, &[K::Ch('M')], "M", A::Messages, "the message log", None),
    b(Ctx::Messages, &[K::Code(KC::Down), K::Ch('j')], "↓/j", A::HelpDown, "scroll the log down", None),
    b(Ctx::Messages, &[K::Code(KC::Up), K::Ch('k')], "↑/k", A::HelpUp, "scroll the log up", None),
    b(Ctx::Messages, &[K::Code(KC::PageDown)], "PgDn", A::HelpPageDown, "a page of the log down", None),
    b(Ctx::Messages, &[K::Code(KC::PageUp)], "PgUp", A::HelpPageUp, "a page of the log up", None),
    b(Ctx::Messages, &[K::Code(KC::Home)], "Home", A::HelpTop, "the first message", None),
    b(Ctx::Messages, &[K::Code(KC::End)], "End", A::HelpBottom, "the last message", None),
    b(Ctx::Messages, &[K::Code(KC::Esc), K::Ch('q'), K::Ch('M')], "Esc/q/M", A::CloseMessages, "close the log", Some(("Esc", "close"))),
    b(Ctx::Global, &[K::Ctrl('z')], "^Z", A::Suspend, "suspend (fg resumes)", Some(("^Z", "suspend"))),
    // the form: first/last field, search, folds
    b(Ctx::Form, &[K::Code(KC::Home), K::Ch('g')], "Home/g", A::FieldFirst, "first field", None),
    b(Ctx::Form, &[K::Code(KC::End), K::Ch('G')], "End/G", A::FieldLast, "last field", None),
    b(Ctx::Form, &[K::Ch('/')], "/", A::SearchStart, "search labels and paths", Some(("/", "search"))),
    b(Ctx::Form, &[K::Ch('n')], "n", A::SearchNext, "next match of the search", None),
    b(Ctx::Form, &[K::Ch('N')], "N", A::SearchPrev, "previous match", None),
    b(Ctx::Form, &[K::Ch('z'), K::Ch(' ')], "z/Space", A::FoldToggle, "fold / unfold the group", Some(("z", "fold"))),
    b(Ctx::Form, &[K::Ch('Z')], "Z", A::FoldAll, "fold all (or unfold all)", None),
    b(Ctx::Search, &[K::Code(KC::Enter)], "Enter", A::SearchKeep, "keep the match", Some(("Enter", "keep"))),
    b(Ctx::Search, &[K::Code(KC::Esc)], "Esc", A::SearchCancel, "back to where it was", Some(("Esc", "back"))),
    b(Ctx::Search, &[K::Code(KC::Down)], "↓", A::SearchNext, "next match", Some(("↑↓", "match"))),
    b(Ctx::Search, &[K::Code(KC::Up)], "↑", A::SearchPrev, "previous match", None),
    b(Ctx::Search, &[K::Code(KC::Backspace)], "Bksp", A::SearchBackspace, "delete a character", None),
    // quitting with unsaved edits
    b(Ctx::Quit, &[K::Ch('s')], "s", A::SaveQuit, "save, then quit", Some(("s", "save and quit"))),
    b(Ctx::Quit, &[K::Ch('y'), K::Ch('q')], "y/q", A::Yes, "quit without saving", Some(("y", "quit, not saving"))),
    b(Ctx::Quit, &[K::Ch('n'), K::Code(KC::Esc)], "n/Esc", A::No, "stay", Some(("n/Esc", "stay"))),
    // another model
    b(Ctx::Global, &[K::Ch('O')], "O", A::OpenModel, "open another model", None),
    b(Ctx::OpenModel, &[K::Code(KC::Up), K::Ch('k')], "↑/k", A::ModelUp, "previous model", None),
    b(Ctx::OpenModel, &[K::Code(KC::Down), K::Ch('j')], "↓/j", A::ModelDown, "next model", Some(("j/k", "model"))),
    b(Ctx::OpenModel, &[K::Code(KC::Enter)], "Enter", A::ModelOpen, "open the model", Some(("Enter", "open"))),
    b(Ctx::OpenModel, &[K::Code(KC::Esc), K::Ch('q')], "Esc/q", A::ModelClose, "close the list", Some(("Esc", "close"))),
];

/// The contexts that are active, most specific first.
pub fn active(mode_ctx: Option<Ctx>, view_ctx: Ctx) -> Vec<Ctx> {
    match mode_ctx {
        Some(m) => vec![m],
        None => vec![view_ctx, Ctx::Global],
    }
}

/// The action of a key in the given contexts.
pub fn lookup(ctxs: &[Ctx], ev: &KeyEvent) -> Option<Action> {
    ctxs.iter().find_map(|c| {
        KEYMAP
            .iter()
            .filter(|bd| bd.ctx == *c)
            .find(|bd| bd.keys.iter().any(|k| k.matches(ev)))
            .map(|bd| bd.action)
    })
}

/// (keys, hint) pairs for the key-hint bar: help and quit first, then the contexts' keys in
/// table order; a binding whose first key a more specific context takes (`Esc` in the studies
/// view) has no hint there.
pub fn hints(ctxs: &[Ctx]) -> Vec<(&'static str, &'static str)> {
    hint_items(ctxs).into_iter().map(|(_, _, h)| h).collect()
}

/// [`hints`] with the action and context of each.
pub fn hint_items(ctxs: &[Ctx]) -> Vec<(Action, Ctx, (&'static str, &'static str))> {
    let shadowed = |bd: &Binding| {
        let i = ctxs.iter().position(|c| *c == bd.ctx).unwrap_or(0);
        bd.keys
            .first()
            .is_some_and(|k| lookup(&ctxs[..i], &k.event()).is_some())
    };
    let all: Vec<&Binding> = ctxs
        .iter()
        .flat_map(|c| KEYMAP.iter().filter(move |bd| bd.ctx == *c))
        .filter(|bd| bd.hint.is_some() && !shadowed(bd))
        .collect();
    let pinned = |bd: &&Binding| matches!(bd.action, Action::Help | Action::Quit);
    let mut out: Vec<&Binding> = all.iter().copied().filter(pinned).collect();
    out.sort_by_key(|bd| bd.action != Action::Help);
    out.extend(all.iter().copied().filter(|bd| !pinned(bd)));
    out.into_iter()
        .filter_map(|bd| bd.hint.map(|h| (bd.action, bd.ctx, h)))
        .collect()
}

/// Help screen lines: (context title, [(key label, description)]).
pub fn help() -> Vec<(&'static str, Vec<(&'static str, &'static str)>)> {
    [
        Ctx::Global,
        Ctx::Charts,
        Ctx::Form,
        Ctx::Studies,
        Ctx::Runs,
        Ctx::Pick,
        Ctx::Naming,
        Ctx::Edit,
        Ctx::Confirm,
        Ctx::Merge,
        Ctx::Recover,
        Ctx::Messages,
        Ctx::Help,
        Ctx::Events,
        Ctx::Search,
        Ctx::Quit,
        Ctx::OpenModel,
        Ctx::ChartPick,
        Ctx::RunInfo,
    ]
    .iter()
    .map(|c| {
        (
            c.title(),
            KEYMAP
                .iter()
                .filter(|bd| bd.ctx == *c)
                .map(|bd| (bd.label, bd.desc))
                .collect(),
        )
    })
    .collect()
}
