//! The machines: every dialect's assembler and executor against the specs, the manuals' examples and hand calculations; the fast loops against the observed ones.

#[path = "../common/mod.rs"]
mod common;

mod assembler;
mod bench_programs;
mod dl205;
mod dl205_boxes;
mod dl205_flow;
mod examples;
mod fast_loop;
mod forcing;
mod ladder;
mod motion;
mod opennet;
mod opennet_plc;
mod overflow_words;
mod plc_fast_loop;
mod positions;
mod product;
mod properties;
mod reference;
mod tml;
mod tml_projects;
mod vendor_examples;
