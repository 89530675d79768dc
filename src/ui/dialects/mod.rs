//! Each dialect's own panels, one folder a dialect, listed once in [`PANELS`] (as rerun's app
//! registers its views: the core never names a panel). A panel appears only for its dialect.

use servoscope_core::registry::Dialect;

use super::panels::DialectPanel;

pub mod dl205;
pub mod opennet;
pub mod plc;
pub mod silverlode;
pub mod tml;

type PanelSet = fn() -> Vec<Box<dyn DialectPanel>>;

/// Every dialect's panels by the dialect's name.
pub static PANELS: &[(&str, PanelSet)] = &[
    ("silverlode", silverlode::panels),
    ("tml", tml::panels),
    ("opennet", opennet::panels),
    ("dl205", dl205::panels),
];

/// The panels of `dialect` (none for a dialect not listed).
pub fn panels(dialect: &Dialect) -> Vec<Box<dyn DialectPanel>> {
    PANELS
        .iter()
        .find(|(name, _)| *name == dialect.name)
        .map_or_else(Vec::new, |(_, panels)| panels())
}

#[cfg(test)]
mod tests {
    use servoscope_core::registry::DIALECTS;

    use super::PANELS;

    #[test]
    fn every_registered_dialect_has_its_panels_listed_once() {
        for dialect in DIALECTS {
            let listed = PANELS.iter().filter(|(n, _)| *n == dialect.name).count();
            assert_eq!(listed, 1, "{} is listed {listed} times", dialect.name);
        }
        assert_eq!(
            PANELS.len(),
            DIALECTS.len(),
            "a panel set for an unknown dialect"
        );
    }
}
