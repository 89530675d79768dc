//! Loops of plain arithmetic compiled to machine code: the fast loop's answer to the vendor's
//! calculation idiom, whose commands are too cheap for one dispatch each.
//!
//! A *loop* is a run of commands from a jump's target up to that jump (`JMP head` or
//! `JMP head, cond`) where every command in between writes one register from registers and
//! constants and sets the flags from the result ([`compilable`]), as the fast loop's own arms do.
//! The first time the fast loop reaches such a head with room for [`MIN_ROUNDS`] rounds, the
//! loop is compiled (Cranelift) into a function that runs whole rounds (the body and the jump
//! taken) with the registers it touches held in machine registers, and returns how many.
//!
//! It only ever stops at the head: a round whose jump would fall through is thrown away and
//! left to the fast loop's arms, which run it command by command (and so record the last command
//! and the flags exactly as ever). Breakpoints, plotted registers and tick limits inside a round
//! therefore never meet compiled code: the caller gives it whole rounds with no stop among them.
//!
//! Compiled code is a cache of the program, shared by every machine running it and freed with
//! it; where Cranelift has no backend (or the `jit` feature is off), loops run in the fast loop.

use std::sync::{Arc, OnceLock};

use super::program::Op;

/// Rounds a compiled loop must have room for before it is worth compiling and calling.
pub const MIN_ROUNDS: u64 = 16;
/// The longest loop compiled, in commands: compiling takes time on the running thread, and a
/// longer body gains nothing from it (its jump is a small part of a round).
pub const MAX_LOOP: usize = 1024;

/// Whether `op` may be part of a compiled loop's body: exactly the fast loop's arms that write
/// one register and set the flags from it (and WRP). Everything else (the executor's own
/// arithmetic, calls, queues) keeps its loop in the fast loop.
pub fn compilable(op: Op) -> bool {
    use Op::*;
    matches!(
        op,
        AddI { .. }
            | SubI { .. }
            | AndI { .. }
            | OrI { .. }
            | XorI { .. }
            | MulI { .. }
            | MulShr16I { .. }
            | AddR { .. }
            | SubR { .. }
            | AndR { .. }
            | OrR { .. }
            | XorR { .. }
            | MulR { .. }
            | MulShr16R { .. }
            | AccAdd { .. }
            | AccSub { .. }
            | AccMul { .. }
            | AccAnd { .. }
            | AccOr { .. }
            | AccXor { .. }
            | AccCopy { .. }
            | AccSave { .. }
            | Inc { .. }
            | Dec { .. }
            | Wrp { .. }
    )
}

/// One loop of a program: commands `head..=end`, `end` the jump back.
pub struct Loop {
    pub head: usize,
    pub end: usize,
    /// The commands `head..=end`, compiled from.
    body: Box<[Op]>,
    code: OnceLock<Option<Compiled>>,
}

impl Loop {
    /// Commands (ticks) a round takes: the body and the jump.
    pub fn round(&self) -> u64 {
        (self.end - self.head + 1) as u64
    }

    /// Whether the loop has run as machine code (it is compiled the first time it runs long).
    pub fn is_compiled(&self) -> bool {
        self.code.get().is_some_and(Option::is_some)
    }

    /// The fast loop at the head with `room` commands left to run: whole rounds, compiled, when
    /// there is room for [`MIN_ROUNDS`] and (with `STOPS`) no command in the loop to stop
    /// before. Returns how many commands ran and the ISW after them. Out of line and cold: the
    /// fast loop lands on a loop's head far less often than it runs commands, and its arms stay
    /// as tight as in a program without loops; the ISW goes by value, so the fast loop's copy
    /// stays in a register.
    #[cold]
    #[inline(never)]
    pub fn enter<const STOPS: bool>(
        &self,
        regs: &mut [i32; super::REGISTERS],
        mut isw: u16,
        room: u64,
        stops: &[bool],
    ) -> (u64, u16) {
        let rounds = room / self.round();
        let clear = !STOPS || (stops.get(self.head..=self.end)).is_some_and(|s| !s.contains(&true));
        if rounds < MIN_ROUNDS || !clear {
            return (0, isw);
        }
        let done = self.run(regs, &mut isw, rounds) * self.round();
        (done, isw)
    }

    /// Run up to `rounds` whole rounds on `regs` and the flags in `isw`, compiling the loop the
    /// first time; how many ran (0 where it cannot be compiled).
    fn run(&self, regs: &mut [i32; super::REGISTERS], isw: &mut u16, rounds: u64) -> u64 {
        match self.code.get_or_init(|| Compiled::new(&self.body)) {
            Some(code) => code.call(regs, isw, rounds),
            None => 0,
        }
    }
}

/// Every loop of a program, found when it is assembled and compiled when first run long.
#[derive(Clone, Default)]
pub struct Loops {
    /// For each command: 1 + the index in `loops` of the loop starting there, else 0.
    head_of: Arc<[u32]>,
    loops: Arc<[Loop]>,
}

impl Loops {
    /// The loops of `flat` (the fast loop's commands): each backward jump whose body is all
    /// [`compilable`], not empty and at most [`MAX_LOOP`] long. (Two jumps back to one head
    /// cannot both qualify: the later one's body holds the earlier jump.)
    pub fn find(flat: &[Op]) -> Loops {
        let mut head_of = vec![0u32; flat.len()];
        let mut loops = Vec::new();
        for (end, &op) in flat.iter().enumerate() {
            let head = match op {
                Op::Jmp { target } | Op::JmpIf { target, .. } => target as usize,
                _ => continue,
            };
            let fits = head < end && end - head < MAX_LOOP;
            if !fits || head_of[head] != 0 || !flat[head..end].iter().all(|&op| compilable(op)) {
                continue;
            }
            loops.push(Loop {
                head,
                end,
                body: flat[head..=end].into(),
                code: OnceLock::new(),
            });
            head_of[head] = loops.len() as u32;
        }
        Loops {
            head_of: head_of.into(),
            loops: loops.into(),
        }
    }

    /// Whether the program has no loop to compile.
    pub fn is_empty(&self) -> bool {
        self.loops.is_empty()
    }

    /// The loop whose head is command `pc`.
    #[inline]
    pub fn at(&self, pc: usize) -> Option<&Loop> {
        let index = *self.head_of.get(pc)?;
        self.loops.get(index.checked_sub(1)? as usize)
    }
}

// A cache derived from the commands: programs are equal when their commands are.
impl PartialEq for Loops {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for Loops {}

impl std::fmt::Debug for Loops {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.loops.iter().map(|l| l.head..=l.end))
            .finish()
    }
}

/// `(regs, isw, rounds) -> rounds run`.
#[cfg(feature = "jit")]
type Entry = unsafe extern "C" fn(*mut i32, *mut u32, u64) -> u64;

/// A compiled loop and the module owning its code.
#[cfg(feature = "jit")]
struct Compiled {
    module: Option<cranelift_jit::JITModule>,
    entry: Entry,
}

/// Without the `jit` feature nothing is ever compiled.
#[cfg(not(feature = "jit"))]
enum Compiled {}

// SAFETY: after compilation the module is touched only to free its code when dropped; the code
// itself is immutable and keeps no state between calls, so any thread may call it.
#[cfg(feature = "jit")]
unsafe impl Send for Compiled {}
#[cfg(feature = "jit")]
unsafe impl Sync for Compiled {}

#[cfg(feature = "jit")]
impl Drop for Compiled {
    fn drop(&mut self) {
        if let Some(module) = self.module.take() {
            // SAFETY: `entry` goes with `self`: no pointer into the code outlives this.
            unsafe { module.free_memory() };
        }
    }
}

#[cfg(not(feature = "jit"))]
impl Compiled {
    fn new(_body: &[Op]) -> Option<Compiled> {
        None
    }

    fn call(&self, _regs: &mut [i32; super::REGISTERS], _isw: &mut u16, _rounds: u64) -> u64 {
        match *self {}
    }
}

#[cfg(feature = "jit")]
impl Compiled {
    fn call(&self, regs: &mut [i32; super::REGISTERS], isw: &mut u16, rounds: u64) -> u64 {
        let mut word = u32::from(*isw);
        // SAFETY: the code reads and writes only `regs[r]` for the registers of the body's
        // commands (each checked < REGISTERS when compiled) and the one word behind `word`.
        let done = unsafe { (self.entry)(regs.as_mut_ptr(), &mut word, rounds) };
        *isw = word as u16;
        done
    }

    /// `body`: the loop's commands, the jump last. None where the host has no backend.
    fn new(body: &[Op]) -> Option<Compiled> {
        let mut module = cranelift_jit::JITModule::new(cranelift_jit::JITBuilder::with_isa(
            host()?,
            cranelift_module::default_libcall_names(),
        ));
        match define(&mut module, body) {
            Some(entry) => Some(Compiled {
                module: Some(module),
                entry,
            }),
            None => {
                // SAFETY: nothing points into the module's code: no function was handed out.
                unsafe { module.free_memory() };
                None
            }
        }
    }
}

/// `body` (the loop's commands, the jump last) as a function in `module`, finalized.
#[cfg(feature = "jit")]
fn define(module: &mut cranelift_jit::JITModule, body: &[Op]) -> Option<Entry> {
    use cranelift_codegen::ir::{AbiParam, BlockArg, InstBuilder, MemFlagsData, types};
    use cranelift_codegen::ir::{UserFuncName, condcodes::IntCC};
    use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
    use cranelift_module::Module;
    use std::collections::BTreeSet;

    use super::isw::{FLAGS, NEGATIVE, POSITIVE, ZERO};

    let (&jump, ops) = body.split_last()?;
    // The registers the body touches, in one order for block parameters.
    let touched: Vec<u8> = ops
        .iter()
        .flat_map(|&op| registers(op))
        .collect::<BTreeSet<u8>>()
        .into_iter()
        .collect();
    if touched.iter().any(|&r| usize::from(r) >= super::REGISTERS) {
        return None;
    }
    let pointer = module.target_config().pointer_type();
    let mut ctx = module.make_context();
    ctx.func.signature.params.push(AbiParam::new(pointer));
    ctx.func.signature.params.push(AbiParam::new(pointer));
    ctx.func.signature.params.push(AbiParam::new(types::I64));
    ctx.func.signature.returns.push(AbiParam::new(types::I64));
    let linkage = cranelift_module::Linkage::Local;
    let id = (module.declare_function("compiled_loop", linkage, &ctx.func.signature)).ok()?;
    ctx.func.name = UserFuncName::user(0, id.as_u32());
    let mut builder_ctx = FunctionBuilderContext::new();
    let mut b = FunctionBuilder::new(&mut ctx.func, &mut builder_ctx);
    let flags = MemFlagsData::trusted();
    let slot = |r: u8| i32::from(r) * 4;

    let entry = b.create_block();
    let head = b.create_block();
    let round = b.create_block();
    let exit = b.create_block();
    b.append_block_params_for_function_params(entry);
    // The state a round starts from: the touched registers, the ISW, the rounds run.
    for block in [head, exit] {
        for _ in 0..touched.len() + 1 {
            b.append_block_param(block, types::I32);
        }
        b.append_block_param(block, types::I64);
    }

    b.switch_to_block(entry);
    let &[regs_at, isw_at, max_rounds] = b.block_params(entry) else {
        return None;
    };
    let mut start: Vec<BlockArg> = Vec::new();
    for &r in &touched {
        start.push(b.ins().load(types::I32, flags, regs_at, slot(r)).into());
    }
    start.push(b.ins().load(types::I32, flags, isw_at, 0).into());
    start.push(b.ins().iconst(types::I64, 0).into());
    b.ins().jump(head, &start);

    b.switch_to_block(head);
    let at_head: Vec<_> = b.block_params(head).to_vec();
    let (&done, state) = at_head.split_last()?;
    let enough = b.ins().icmp(IntCC::Equal, done, max_rounds);
    let as_is: Vec<BlockArg> = at_head.iter().map(|&v| v.into()).collect();
    b.ins().brif(enough, exit, &as_is, round, &[]);

    b.switch_to_block(round);
    let mut value: Vec<_> = state[..touched.len()].to_vec();
    let mut isw = state[touched.len()];
    for &op in ops {
        let index = |r: u8| touched.binary_search(&r).ok();
        let (dst, v) = compute(&mut b, op, |r| Some(value[index(r)?]))?;
        let dst = index(dst)?;
        value[dst] = v;
        if !matches!(op, Op::Wrp { .. }) {
            // The flags from the result, as `flag_bits`; the unused ones are dead code.
            let is_zero = b.ins().icmp_imm_s(IntCC::Equal, v, 0);
            let is_positive = b.ins().icmp_imm_s(IntCC::SignedGreaterThan, v, 0);
            let zero = b.ins().iconst(types::I32, i64::from(ZERO));
            let positive = b.ins().iconst(types::I32, i64::from(POSITIVE));
            let negative = b.ins().iconst(types::I32, i64::from(NEGATIVE));
            let sign = b.ins().select(is_positive, positive, negative);
            let bits = b.ins().select(is_zero, zero, sign);
            let kept = b.ins().band_imm_u(isw, i64::from(!FLAGS));
            isw = b.ins().bor(kept, bits);
        }
    }
    let next = b.ins().iadd_imm_s(done, 1);
    let mut after: Vec<BlockArg> = value.iter().map(|&v| v.into()).collect();
    after.push(isw.into());
    after.push(next.into());
    match jump {
        Op::Jmp { .. } => {
            b.ins().jump(head, &after);
        }
        Op::JmpIf { bit, want, .. } => {
            let shifted = b.ins().ushr_imm_u(isw, i64::from(bit));
            let bit = b.ins().band_imm_u(shifted, 1);
            let taken = b.ins().icmp_imm_u(IntCC::Equal, bit, i64::from(want));
            // Not taken: the round is thrown away, the state is the head's.
            b.ins().brif(taken, head, &after, exit, &as_is);
        }
        _ => return None,
    }

    b.switch_to_block(exit);
    let at_exit: Vec<_> = b.block_params(exit).to_vec();
    for (&r, &v) in touched.iter().zip(&at_exit) {
        b.ins().store(flags, v, regs_at, slot(r));
    }
    b.ins().store(flags, at_exit[touched.len()], isw_at, 0);
    b.ins().return_(&[at_exit[touched.len() + 1]]);
    b.seal_all_blocks();
    b.finalize(module.target_config());

    module.define_function(id, &mut ctx).ok()?;
    module.clear_context(&mut ctx);
    module.finalize_definitions().ok()?;
    let code = module.get_finalized_function(id);
    // SAFETY: the function was declared with exactly `Entry`'s signature, in the host's
    // default calling convention, which is `extern "C"`.
    Some(unsafe { std::mem::transmute::<*const u8, Entry>(code) })
}

/// The registers `op` reads or writes (R10 for the accumulator's).
#[cfg(feature = "jit")]
fn registers(op: Op) -> Vec<u8> {
    use Op::*;
    match op {
        AddI { res, a, .. }
        | SubI { res, a, .. }
        | AndI { res, a, .. }
        | OrI { res, a, .. }
        | XorI { res, a, .. }
        | MulI { res, a, .. }
        | MulShr16I { res, a, .. } => vec![res, a],
        AddR { res, a, b }
        | SubR { res, a, b }
        | AndR { res, a, b }
        | OrR { res, a, b }
        | XorR { res, a, b }
        | MulR { res, a, b }
        | MulShr16R { res, a, b } => vec![res, a, b],
        AccAdd { r }
        | AccSub { r }
        | AccMul { r }
        | AccAnd { r }
        | AccOr { r }
        | AccXor { r }
        | AccCopy { r }
        | AccSave { r } => vec![10, r],
        Inc { r } | Dec { r } | Wrp { r, .. } => vec![r],
        _ => Vec::new(),
    }
}

/// `op`'s register written and its value, from the registers' values `read`: the fast loop's
/// arms, in Cranelift.
#[cfg(feature = "jit")]
fn compute(
    b: &mut cranelift_frontend::FunctionBuilder<'_>,
    op: Op,
    read: impl Fn(u8) -> Option<cranelift_codegen::ir::Value>,
) -> Option<(u8, cranelift_codegen::ir::Value)> {
    use Op::*;
    use cranelift_codegen::ir::{InstBuilder, types};

    enum Binary {
        Add,
        Sub,
        And,
        Or,
        Xor,
        Mul,
        /// `((x as i64) * (y as i64)) >> 16`, kept to 32 bits.
        MulShr16,
    }
    use Binary::*;
    let constant = |b: &mut cranelift_frontend::FunctionBuilder<'_>, d: i32| {
        b.ins().iconst(types::I32, i64::from(d as u32))
    };
    let (dst, binary, x, y) = match op {
        AddI { res, a, d } => (res, Add, read(a)?, constant(b, d)),
        SubI { res, a, d } => (res, Sub, read(a)?, constant(b, d)),
        AndI { res, a, d } => (res, And, read(a)?, constant(b, d)),
        OrI { res, a, d } => (res, Or, read(a)?, constant(b, d)),
        XorI { res, a, d } => (res, Xor, read(a)?, constant(b, d)),
        MulI { res, a, d } => (res, Mul, read(a)?, constant(b, d)),
        MulShr16I { res, a, d } => (res, MulShr16, read(a)?, constant(b, d)),
        AddR { res, a, b: r } => (res, Add, read(a)?, read(r)?),
        SubR { res, a, b: r } => (res, Sub, read(a)?, read(r)?),
        AndR { res, a, b: r } => (res, And, read(a)?, read(r)?),
        OrR { res, a, b: r } => (res, Or, read(a)?, read(r)?),
        XorR { res, a, b: r } => (res, Xor, read(a)?, read(r)?),
        MulR { res, a, b: r } => (res, Mul, read(a)?, read(r)?),
        MulShr16R { res, a, b: r } => (res, MulShr16, read(a)?, read(r)?),
        AccAdd { r } => (10, Add, read(10)?, read(r)?),
        AccSub { r } => (10, Sub, read(10)?, read(r)?),
        AccMul { r } => (10, Mul, read(10)?, read(r)?),
        AccAnd { r } => (10, And, read(10)?, read(r)?),
        AccOr { r } => (10, Or, read(10)?, read(r)?),
        AccXor { r } => (10, Xor, read(10)?, read(r)?),
        Inc { r } => (r, Add, read(r)?, constant(b, 1)),
        Dec { r } => (r, Sub, read(r)?, constant(b, 1)),
        AccCopy { r } => return Some((10, read(r)?)),
        AccSave { r } => return Some((r, read(10)?)),
        Wrp { r, value } => return Some((r, constant(b, value))),
        _ => return None,
    };
    let v = match binary {
        Add => b.ins().iadd(x, y),
        Sub => b.ins().isub(x, y),
        And => b.ins().band(x, y),
        Or => b.ins().bor(x, y),
        Xor => b.ins().bxor(x, y),
        Mul => b.ins().imul(x, y),
        MulShr16 => {
            let x = b.ins().sextend(types::I64, x);
            let y = b.ins().sextend(types::I64, y);
            let product = b.ins().imul(x, y);
            let shifted = b.ins().sshr_imm_u(product, 16);
            b.ins().ireduce(types::I32, shifted)
        }
    };
    Some((dst, v))
}

/// The host's code generator, built once; None where Cranelift has no backend for it.
#[cfg(feature = "jit")]
fn host() -> Option<cranelift_codegen::isa::OwnedTargetIsa> {
    static HOST: OnceLock<Option<cranelift_codegen::isa::OwnedTargetIsa>> = OnceLock::new();
    HOST.get_or_init(|| {
        use cranelift_codegen::settings::{self, Configurable};
        let mut flags = settings::builder();
        flags.set("opt_level", "speed").ok()?;
        flags.set("use_colocated_libcalls", "false").ok()?;
        flags.set("is_pic", "false").ok()?;
        cranelift_native::builder()
            .ok()?
            .finish(settings::Flags::new(flags))
            .ok()
    })
    .clone()
}
