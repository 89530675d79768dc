//! SilverLode's own panels: the queue rings and the product of the last multiply.

use crate::ui::panels::DialectPanel;

pub mod product;
pub mod queues;

pub fn panels() -> Vec<Box<dyn DialectPanel>> {
    vec![
        Box::new(queues::QueuePanel::default()),
        Box::new(product::ProductPanel::default()),
    ]
}
