//! The arguments several commands share: a model with its `--set` overrides, an integration
//! method, a study of the paper.

use clap::builder::PossibleValue;
use clap::{Args, ValueEnum};
use deckspin::methods::Method;
use std::path::PathBuf;

/// A model file and the scalars overridden in it.
#[derive(Args, Clone, Debug)]
pub struct ModelArgs {
    /// Model file (TOML: a bridge or a general scene).
    #[arg(value_name = "MODEL")]
    pub path: PathBuf,
    /// Override a scalar by its dotted TOML path (key.path=value); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// An integration method by its name in model files ([`Method::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MethodArg(pub Method);

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        const ALL: [MethodArg; Method::ALL.len()] = {
            let mut all = [MethodArg(Method::Event); Method::ALL.len()];
            let mut k = 0;
            while k < all.len() {
                all[k] = MethodArg(Method::ALL[k]);
                k += 1;
            }
            all
        };
        &ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()).help(self.0.title()))
    }
}

/// The paper's studies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StudyKind {
    /// Peak rotation against PGA (Fig. 7).
    Pga,
    /// The increase of the peak rotation against μ (Fig. 8).
    Mu,
}
