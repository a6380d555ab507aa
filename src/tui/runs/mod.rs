//! The runs of the workbench: a run's charted history and what it carries besides
//! (`data`, `results`, `series`), its events at the cursor (`nav`), the run list and its files
//! (`list`, `store`, `info`), and the exports into the model's output folder (`export`,
//! `out_folder`).

pub mod data;
pub mod export;
pub mod info;
pub mod list;
pub mod nav;
pub mod out_folder;
pub mod series;
pub mod store;
