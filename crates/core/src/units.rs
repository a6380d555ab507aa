//! The model's unit system, the top-level `units` key: `"SI-kN"` (t, kN, m, s; the default),
//! `"SI"` (kg, N, m, s) or `"kip-in"` (kip·s²/in, kip, in, s). The engine is unit-free (any
//! consistent set); the system names each quantity's unit and converts records, which are in g.

use std::fmt;

/// A consistent set of units: mass = force · s² / length.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UnitSystem {
    /// t, kN, m, s (energy kJ).
    #[default]
    SiKn,
    /// kg, N, m, s (energy J).
    Si,
    /// kip·s²/in, kip, in, s (energy kip·in).
    KipIn,
}

/// A quantity whose unit depends on the system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Mass.
    Mass,
    /// Mass moment of inertia (mass · length²).
    Inertia,
    /// Length.
    Length,
    /// Time.
    Time,
    /// Force.
    Force,
    /// Force / length.
    Stiffness,
    /// Force · time / length.
    Damping,
    /// Force · length.
    Moment,
    /// Moment / rad.
    RotationalStiffness,
    /// Moment · time / rad.
    RotationalDamping,
    /// Energy (force · length).
    Energy,
    /// Length / time.
    Velocity,
    /// Length / time².
    Acceleration,
    /// Plane angle, rad.
    Angle,
    /// Plane angle, degrees.
    Degrees,
    /// Rotation rate, rad/s.
    AngularVelocity,
}

/// The names the `units` key takes, with their systems.
pub(crate) const NAMES: [(&str, UnitSystem); 3] = [
    ("SI-kN", UnitSystem::SiKn),
    ("SI", UnitSystem::Si),
    ("kip-in", UnitSystem::KipIn),
];

/// Standard gravity, m/s².
pub const G_SI: f64 = 9.80665;

/// kN per kip (1 lbf = 4.4482216152605 N exactly).
const KN_PER_KIP: f64 = 4.448_221_615_260_5;

/// Inches per metre (1 in = 0.0254 m exactly).
const IN_PER_M: f64 = 1.0 / 0.0254;

impl UnitSystem {
    /// The system a `units` value names (exactly one of [`NAMES`], case-insensitive).
    pub fn parse(s: &str) -> Result<UnitSystem, String> {
        NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(s.trim()))
            .map(|(_, u)| *u)
            .ok_or_else(|| {
                let names: Vec<&str> = NAMES.iter().map(|(n, _)| *n).collect();
                format!("unknown unit system '{s}' (one of {})", names.join(", "))
            })
    }

    /// The name in model files (`units = "…"`).
    pub fn name(self) -> &'static str {
        match self {
            UnitSystem::SiKn => "SI-kN",
            UnitSystem::Si => "SI",
            UnitSystem::KipIn => "kip-in",
        }
    }

    /// Length units per metre (records and their processing are in m and g).
    pub(crate) fn per_metre(self) -> f64 {
        match self {
            UnitSystem::SiKn | UnitSystem::Si => 1.0,
            UnitSystem::KipIn => IN_PER_M,
        }
    }

    /// Force units per kN.
    pub(crate) fn per_kilonewton(self) -> f64 {
        match self {
            UnitSystem::SiKn => 1.0,
            UnitSystem::Si => 1000.0,
            UnitSystem::KipIn => 1.0 / KN_PER_KIP,
        }
    }

    /// Standard gravity in the system's acceleration unit.
    pub fn g(self) -> f64 {
        G_SI * self.per_metre()
    }

    /// The unit of `q`, as printed (UTF-8; [`UnitSystem::ascii`] for plain terminals).
    pub fn unit(self, q: Quantity) -> &'static str {
        use Quantity as Q;
        let (mass, inertia, len, force, energy) = match self {
            UnitSystem::SiKn => ("t", "t·m²", "m", "kN", "kJ"),
            UnitSystem::Si => ("kg", "kg·m²", "m", "N", "J"),
            UnitSystem::KipIn => ("kip·s²/in", "kip·s²·in", "in", "kip", "kip·in"),
        };
        match (q, self) {
            (Q::Mass, _) => mass,
            (Q::Inertia, _) => inertia,
            (Q::Length, _) => len,
            (Q::Time, _) => "s",
            (Q::Force, _) => force,
            (Q::Energy, _) => energy,
            (Q::Angle, _) => "rad",
            (Q::Degrees, _) => "°",
            (Q::AngularVelocity, _) => "rad/s",
            (Q::Stiffness, UnitSystem::SiKn) => "kN/m",
            (Q::Stiffness, UnitSystem::Si) => "N/m",
            (Q::Stiffness, UnitSystem::KipIn) => "kip/in",
            (Q::Damping, UnitSystem::SiKn) => "kN·s/m",
            (Q::Damping, UnitSystem::Si) => "N·s/m",
            (Q::Damping, UnitSystem::KipIn) => "kip·s/in",
            (Q::Moment, UnitSystem::SiKn) => "kN·m",
            (Q::Moment, UnitSystem::Si) => "N·m",
            (Q::Moment, UnitSystem::KipIn) => "kip·in",
            (Q::RotationalStiffness, UnitSystem::SiKn) => "kN·m/rad",
            (Q::RotationalStiffness, UnitSystem::Si) => "N·m/rad",
            (Q::RotationalStiffness, UnitSystem::KipIn) => "kip·in/rad",
            (Q::RotationalDamping, UnitSystem::SiKn) => "kN·m·s/rad",
            (Q::RotationalDamping, UnitSystem::Si) => "N·m·s/rad",
            (Q::RotationalDamping, UnitSystem::KipIn) => "kip·in·s/rad",
            (Q::Velocity, UnitSystem::KipIn) => "in/s",
            (Q::Velocity, _) => "m/s",
            (Q::Acceleration, UnitSystem::KipIn) => "in/s²",
            (Q::Acceleration, _) => "m/s²",
        }
    }

    /// [`UnitSystem::unit`] in ASCII (`·` → `*`, `²` → `^2`, `°` → `deg`).
    pub fn ascii(self, q: Quantity) -> String {
        ascii_unit(self.unit(q))
    }
}

/// A unit in ASCII: `·` → `*`, `²` → `^2`, `°` → `deg`, `µ` → `u`.
pub fn ascii_unit(u: &str) -> String {
    u.replace('·', "*")
        .replace('²', "^2")
        .replace('°', "deg")
        .replace('µ', "u")
}

impl fmt::Display for UnitSystem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for (n, u) in NAMES {
            assert_eq!(UnitSystem::parse(n), Ok(u));
            assert_eq!(UnitSystem::parse(&n.to_lowercase()), Ok(u));
            assert_eq!(u.name(), n);
        }
        let e = UnitSystem::parse("cgs").unwrap_err();
        assert!(e.contains("SI-kN, SI, kip-in"), "{e}");
    }

    #[test]
    fn each_system_is_consistent_mass_is_force_s2_per_length() {
        // 1 kip = 4448.2216152605 N, 1 in = 0.0254 m: 1 kip·s²/in = 175126.835… kg
        let kip: f64 = 4448.2216152605;
        let kg_per = [
            (UnitSystem::SiKn, 1000.0_f64, 1000.0_f64, 1.0_f64),
            (UnitSystem::Si, 1.0, 1.0, 1.0),
            (UnitSystem::KipIn, kip / 0.0254, kip, 0.0254),
        ];
        for (u, mass_kg, force_n, len_m) in kg_per {
            // F = m a: force_n == mass_kg · len_m / s²
            assert!((force_n - mass_kg * len_m).abs() <= 1e-9 * force_n, "{u}");
            assert!((u.per_metre() * len_m - 1.0).abs() < 1e-15, "{u}");
        }
        assert_eq!(UnitSystem::SiKn.g(), 9.80665);
        assert!((UnitSystem::KipIn.g() - 386.088_582_677).abs() < 1e-8);
    }

    #[test]
    fn ascii_units_have_no_byte_above_0x7e() {
        for (_, u) in NAMES {
            for q in [
                Quantity::Inertia,
                Quantity::Damping,
                Quantity::Acceleration,
                Quantity::Degrees,
                Quantity::RotationalDamping,
            ] {
                assert!(u.ascii(q).bytes().all(|b| b <= 0x7e), "{}", u.ascii(q));
            }
        }
        assert_eq!(UnitSystem::SiKn.ascii(Quantity::Inertia), "t*m^2");
    }
}
