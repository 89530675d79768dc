//! The machines: every dialect's assembler and executor against the specs, the manuals' examples and hand calculations; the fast loops against the observed ones.

#[path = "../common/mod.rs"]
mod common;

mod bench_programs;
mod dl205;
mod dl205_boxes;
mod dl205_flow;
mod fast_loop;
mod forcing;
mod ladder;
mod opennet;
mod opennet_plc;
mod overflow_words;
mod plc_fast_loop;
mod positions;
mod product;
mod reference;
mod silverlode_assembler;
mod silverlode_examples;
mod silverlode_motion;
mod silverlode_properties;
mod silverlode_vendor_examples;
mod tml;
mod tml_projects;
