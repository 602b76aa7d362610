//! The built-in scenes, embedded in the binary (the files live in `scenes/`).

/// A built-in scene: its name and TOML text.
#[derive(Clone, Copy, Debug)]
pub struct Builtin {
    /// The name (`quatrot run NAME`).
    pub name: &'static str,
    /// The scene file's text.
    pub toml: &'static str,
}

macro_rules! builtin {
    ($name:literal) => {
        Builtin {
            name: $name,
            toml: include_str!(concat!("../../scenes/", $name, ".toml")),
        }
    };
}

/// Every built-in scene, in the order `quatrot scenes` lists them.
pub const BUILTINS: &[Builtin] = &[
    builtin!("free_spherical_top"),
    builtin!("free_asymmetric_top"),
    builtin!("dipole_in_field"),
    builtin!("dipole_lattice_sc"),
    builtin!("dipole_lattice_sc_cutoff"),
    builtin!("dipole_lattice_sc_langevin"),
    builtin!("quadrupole_lattice_fcc"),
    builtin!("multipole_tops_bcc"),
    builtin!("stockmayer_fluid"),
    builtin!("lewis_wahnstrom_otp"),
    builtin!("spce_water_512"),
    builtin!("spce_water_4096"),
];

/// The built-in scene called `name`, if any.
pub fn builtin(name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|b| b.name == name)
}
