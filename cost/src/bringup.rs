//! FPGA bring-up (issue #8): an 8N1 UART receiver and transmitter built in the
//! DSL, and a wrapper that puts a generated unit behind them.
//!
//! Protocol of the wrapper: the host sends one input record as bytes, in the
//! layout of a binary `rtlvec` record (docs/vectors.md): every data input port
//! in port-list order, `ceil(width/8)` bytes each, little-endian. When the
//! last byte arrives the wrapper presents the record with `in_valid` for one
//! cycle; `latency` cycles later it captures the data outputs and sends them
//! back in the same layout. The host waits for the whole answer before it
//! sends the next record (a record sent earlier is still received, but the
//! answer of the previous one is overwritten if it is still being sent).
//! Bits above a port's width in the received bytes are ignored; bits above an
//! output's width are sent as zero.
//!
//! The wrapper has the unit's `clk` and synchronous active-high `rst`;
//! [`board_top`] adds a power-on reset for boards without a reset pin.

use rtl_gen::arith::int::{self, bits_for, dec, inc, is};
use rtl_gen::builder::{ModuleBuilder, Sig};
use rtl_gen::ir::{control, Module, Ty};
use rtl_gen::ports::{self, Record, Visit, Walk};
use std::sync::Arc;

/// The module name of the receiver for `cycles_per_bit`.
pub fn uart_rx_name(cycles_per_bit: u32) -> String {
    format!("uart_rx_c{cycles_per_bit}")
}

/// The module name of the transmitter for `cycles_per_bit`.
pub fn uart_tx_name(cycles_per_bit: u32) -> String {
    format!("uart_tx_c{cycles_per_bit}")
}

/// The receiver's input: the serial line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UartRxIn<T> {
    /// the line, idle high
    pub rx: T,
}

impl<T: Copy> Record<T> for UartRxIn<T> {
    type Config = ();
    fn walk<V: Visit<T>>(_: &(), w: &mut Walk<'_, T, Self, V>) -> Self {
        UartRxIn {
            rx: w.one("rx", Ty::Bool, |r| r.rx),
        }
    }
}

/// The receiver's outputs: a byte and its one-cycle strobe.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UartRxOut<T> {
    /// a byte arrived this cycle
    pub valid: T,
    /// the byte
    pub data: T,
}

impl<T: Copy> Record<T> for UartRxOut<T> {
    type Config = ();
    fn walk<V: Visit<T>>(_: &(), w: &mut Walk<'_, T, Self, V>) -> Self {
        UartRxOut {
            valid: w.one("valid", Ty::Bool, |r| r.valid),
            data: w.one("data", Ty::UInt(8), |r| r.data),
        }
    }
}

/// The transmitter's inputs: a byte to send and its request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UartTxIn<T> {
    /// send `data` (taken when not busy)
    pub start: T,
    /// the byte
    pub data: T,
}

impl<T: Copy> Record<T> for UartTxIn<T> {
    type Config = ();
    fn walk<V: Visit<T>>(_: &(), w: &mut Walk<'_, T, Self, V>) -> Self {
        UartTxIn {
            start: w.one("start", Ty::Bool, |r| r.start),
            data: w.one("data", Ty::UInt(8), |r| r.data),
        }
    }
}

/// The transmitter's outputs: the serial line and its busy flag.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UartTxOut<T> {
    /// the line, idle high
    pub tx: T,
    /// a frame is being sent
    pub busy: T,
}

impl<T: Copy> Record<T> for UartTxOut<T> {
    type Config = ();
    fn walk<V: Visit<T>>(_: &(), w: &mut Walk<'_, T, Self, V>) -> Self {
        UartTxOut {
            tx: w.one("tx", Ty::Bool, |r| r.tx),
            busy: w.one("busy", Ty::Bool, |r| r.busy),
        }
    }
}

/// 8N1 UART receiver, `cycles_per_bit` clock cycles a bit (at least 4).
///
/// Input `rx` (idle high) passes a two-flop synchroniser. A falling edge
/// starts a frame; the start bit is sampled half a bit later (a glitch
/// shorter than that is ignored), the eight data bits (least significant
/// first) and the stop bit one bit apart from there. Outputs: `valid` high
/// for one cycle with `data` when a frame ends with a stop bit of 1; a frame
/// with a stop bit of 0 is dropped.
pub fn uart_rx(cycles_per_bit: u32) -> Arc<Module> {
    assert!(cycles_per_bit >= 4, "a bit needs at least 4 clock cycles");
    let mut m = ModuleBuilder::new(uart_rx_name(cycles_per_bit));
    m.describe(format!(
        "UART receiver, 8N1, {cycles_per_bit} clock cycles per bit; valid pulses for one cycle with each byte."
    ));
    m.param("cycles_per_bit", cycles_per_bit);
    let UartRxIn { rx } = ports::declare_inputs(&mut m, &());
    let cw = bits_for(cycles_per_bit as u64);
    let tru = m.bool(true);
    let fls = m.bool(false);

    let sync1 = m.reg("rx_sync1", Ty::Bool, Some(1));
    let sync2 = m.reg("rx_sync2", Ty::Bool, Some(1));
    let busy = m.reg("busy", Ty::Bool, Some(0));
    let count = m.reg("count", Ty::UInt(cw), Some(0));
    let index = m.reg("bit_index", Ty::UInt(4), Some(0));
    let shift = m.reg("shift", Ty::UInt(8), None);
    let valid = m.reg("valid_r", Ty::Bool, Some(0));

    m.set_next(sync1, rx, None);
    m.set_next(sync2, sync1.q, None);
    let line = sync2.q;

    let idle = m.not(busy.q);
    let low = m.not(line);
    let start = m.and(idle, low);
    let start = m.name(start, "start_edge");
    let tick = is(&mut m, count.q, 0);
    let sample = m.and(busy.q, tick);
    let sample = m.name(sample, "sample");
    let at_start = is(&mut m, index.q, 0);
    let at_stop = is(&mut m, index.q, 9);
    let false_start = m.and(at_start, line);
    let frame_end = m.or(false_start, at_stop);
    let busy_clear = m.and(sample, frame_end);

    // busy: set by a falling edge, cleared after the stop bit or a false start
    let busy_next = m.mux(start, tru, busy.q);
    let busy_next = m.mux(busy_clear, fls, busy_next);
    m.set_next(busy, busy_next, None);

    // count: half a bit to the middle of the start bit, then whole bits
    let half = m.uint(cw, (cycles_per_bit / 2 - 1) as u128);
    let full = m.uint(cw, (cycles_per_bit - 1) as u128);
    let count_down = dec(&mut m, count.q);
    let count_next = m.mux(tick, full, count_down);
    let count_next = m.mux(start, half, count_next);
    m.set_next(count, count_next, None);

    let zero4 = m.uint(4, 0);
    let index_up = inc(&mut m, index.q);
    let index_next = m.mux(sample, index_up, index.q);
    let index_next = m.mux(start, zero4, index_next);
    m.set_next(index, index_next, None);

    // data bits 1..=8 shift in from the top, least significant first
    let upper = m.slice(shift.q, 7, 1);
    let shifted = m.cat(&[line, upper]);
    let not_start = m.not(at_start);
    let not_stop = m.not(at_stop);
    let in_data = m.and(not_start, not_stop);
    let take = m.and(sample, in_data);
    m.set_next(shift, shifted, Some(take));

    let good = m.and(at_stop, line);
    let good = m.and(sample, good);
    m.set_next(valid, good, None);

    let outputs = UartRxOut {
        valid: valid.q,
        data: shift.q,
    };
    ports::declare_outputs(&mut m, &(), &outputs);
    Arc::new(m.finish().expect("uart_rx is type-correct"))
}

/// 8N1 UART transmitter, `cycles_per_bit` clock cycles a bit (at least 2).
///
/// Inputs `start` and `data`: a byte is taken when `start` is high and `busy`
/// is low. Outputs: `tx` (idle high, driven by a flip-flop) and `busy`, high
/// from the cycle after `start` until the end of the stop bit.
pub fn uart_tx(cycles_per_bit: u32) -> Arc<Module> {
    assert!(cycles_per_bit >= 2, "a bit needs at least 2 clock cycles");
    let mut m = ModuleBuilder::new(uart_tx_name(cycles_per_bit));
    m.describe(format!(
        "UART transmitter, 8N1, {cycles_per_bit} clock cycles per bit; takes data when start is high and busy low."
    ));
    m.param("cycles_per_bit", cycles_per_bit);
    let UartTxIn { start, data } = ports::declare_inputs(&mut m, &());
    let cw = bits_for(cycles_per_bit as u64);

    // frame: stop bit, data (msb .. lsb), start bit; bit 0 drives the line
    let frame = m.reg("frame", Ty::UInt(10), Some(0x3ff));
    let bits_left = m.reg("bits_left", Ty::UInt(4), Some(0));
    let count = m.reg("count", Ty::UInt(cw), Some(0));

    let busy = m.any_set(bits_left.q);
    let busy = m.name(busy, "busy_w");
    let idle = m.not(busy);
    let load = m.and(start, idle);
    let load = m.name(load, "load");
    let tick = is(&mut m, count.q, 0);
    let shift = m.and(busy, tick);
    let shift = m.name(shift, "shift");

    let one = m.uint(1, 1);
    let zero = m.uint(1, 0);
    let loaded = m.cat(&[one, data, zero]);
    let upper = m.slice(frame.q, 9, 1);
    let shifted = m.cat(&[one, upper]);
    let frame_next = m.mux(shift, shifted, frame.q);
    let frame_next = m.mux(load, loaded, frame_next);
    m.set_next(frame, frame_next, None);

    let ten = m.uint(4, 10);
    let left_down = dec(&mut m, bits_left.q);
    let left_next = m.mux(shift, left_down, bits_left.q);
    let left_next = m.mux(load, ten, left_next);
    m.set_next(bits_left, left_next, None);

    let full = m.uint(cw, (cycles_per_bit - 1) as u128);
    let count_down = dec(&mut m, count.q);
    let count_next = m.mux(tick, full, count_down);
    let count_next = m.mux(load, full, count_next);
    m.set_next(count, count_next, None);

    let tx = m.bit_at(frame.q, 0);
    ports::declare_outputs(&mut m, &(), &UartTxOut { tx, busy });
    Arc::new(m.finish().expect("uart_tx is type-correct"))
}

/// Bytes of one record of `widths` (ceil(width/8) each).
pub fn record_bytes(widths: impl IntoIterator<Item = u32>) -> usize {
    widths.into_iter().map(|w| w.div_ceil(8) as usize).sum()
}

/// Packs one record: each value little-endian in ceil(width/8) bytes.
pub fn pack(values: &[u64], widths: &[u32], out: &mut Vec<u8>) {
    for (v, w) in values.iter().zip(widths) {
        for b in 0..w.div_ceil(8) {
            out.push((v >> (8 * b)) as u8);
        }
    }
}

/// Unpacks one record of `widths` from `bytes` (which holds exactly one record).
pub fn unpack(bytes: &[u8], widths: &[u32]) -> Vec<u64> {
    let mut at = 0;
    widths
        .iter()
        .map(|w| {
            let n = w.div_ceil(8) as usize;
            let v = bytes[at..at + n]
                .iter()
                .rev()
                .fold(0u64, |acc, b| (acc << 8) | *b as u64);
            at += n;
            v
        })
        .collect()
}

/// The module name of the wrapper of `unit` at `cycles_per_bit`.
pub fn wrapper_name(unit: &Module, cycles_per_bit: u32) -> String {
    format!("bringup_{}_c{cycles_per_bit}", unit.name)
}

/// The bring-up wrapper: `unit` (a module with the valid handshake) behind a
/// UART at `cycles_per_bit`. Ports `clk`, `rst`, `rx` in, `tx` out. See the
/// module documentation for the byte protocol.
pub fn wrapper(unit: &Arc<Module>, cycles_per_bit: u32) -> Module {
    let hs = unit
        .handshake
        .expect("the wrapped unit has the in_valid/out_valid handshake");
    let in_ports: Vec<_> = unit.data_inputs().to_vec();
    let out_ports: Vec<_> = unit.data_outputs().iter().map(|(p, _)| p.clone()).collect();
    let n_in = record_bytes(in_ports.iter().map(|p| p.ty.width()));
    let n_out = record_bytes(out_ports.iter().map(|p| p.ty.width()));
    assert!(
        n_in >= 1 && n_out >= 1,
        "the unit has data inputs and outputs"
    );

    let mut m = ModuleBuilder::new(wrapper_name(unit, cycles_per_bit));
    m.describe(format!(
        "FPGA bring-up wrapper of {}: receives {n_in}-byte input records on rx (8N1 UART, \
         {cycles_per_bit} clock cycles per bit; rtlvec binary layout: ports in order, \
         ceil(width/8) bytes each, little-endian), presents each with in_valid for one cycle, \
         and sends the {n_out}-byte output record back on tx {} cycles later.",
        unit.name, hs.latency
    ));
    m.param("unit", &unit.name)
        .param("cycles_per_bit", cycles_per_bit)
        .param("in_bytes", n_in)
        .param("out_bytes", n_out);
    let rx = m.input("rx", Ty::Bool);

    // receive: a shift register of bytes; the first byte of a record ends up in in_buf0
    let urx: UartRxOut<Sig> = ports::instance(
        &mut m,
        "u_rx",
        &uart_rx(cycles_per_bit),
        &(),
        &UartRxIn { rx },
        &(),
    );
    let (byte_valid, byte) = (urx.valid, urx.data);
    let in_buf: Vec<_> = (0..n_in)
        .map(|i| m.reg(&format!("in_buf{i}"), Ty::UInt(8), None))
        .collect();
    for i in 0..n_in {
        let next = if i + 1 < n_in { in_buf[i + 1].q } else { byte };
        m.set_next(in_buf[i], next, Some(byte_valid));
    }
    let iw = bits_for(n_in as u64 - 1);
    let in_count = m.reg("in_count", Ty::UInt(iw), Some(0));
    let last_byte = is(&mut m, in_count.q, n_in as u64 - 1);
    let record_done = m.and(byte_valid, last_byte);
    let record_done = m.name(record_done, "record_done");
    let zero_iw = m.uint(iw, 0);
    let count_up = inc(&mut m, in_count.q);
    let count_next = m.mux(last_byte, zero_iw, count_up);
    m.set_next(in_count, count_next, Some(byte_valid));
    let fire = m.reg("fire", Ty::Bool, Some(0));
    m.set_next(fire, record_done, None);

    let mut conns: Vec<(String, Sig)> = vec![(control::IN_VALID.into(), fire.q)];
    if hs.ready {
        // one record at a time, its answer always taken: never stalled, so
        // in_ready stays high and the latency is the core's
        let always = m.bool(true);
        conns.push((control::OUT_READY.into(), always));
    }
    let mut at = 0usize;
    for p in &in_ports {
        let w = p.ty.width();
        let n = w.div_ceil(8) as usize;
        let bytes: Vec<Sig> = in_buf[at..at + n].iter().rev().map(|r| r.q).collect();
        let all = m.cat(&bytes);
        let bits = m.slice(all, w - 1, 0);
        let v = m.cast(bits, p.ty);
        conns.push((p.name.clone(), v));
        at += n;
    }
    let outs = m.instance("u_unit", unit, &conns);
    // the unit's outputs belong to stage `latency`; the send side lives there
    for _ in 0..hs.latency {
        m.stage();
    }
    // a unit with the handshake has out_valid first (then in_ready with
    // valid/ready), then its data outputs
    let out_valid = outs.all()[0];
    let data_outputs = &outs.all()[hs.control_ports()..];
    let mut record = Vec::with_capacity(n_out);
    for &v in data_outputs {
        let w = v.width();
        for b in 0..w.div_ceil(8) {
            let hi = (8 * b + 7).min(w - 1);
            let part = m.slice(v, hi, 8 * b);
            record.push(int::zext(&mut m, part, 8));
        }
    }

    // send: load the record on out_valid, then one byte per idle transmitter
    let out_buf: Vec<_> = (0..n_out)
        .map(|i| m.reg(&format!("out_buf{i}"), Ty::UInt(8), None))
        .collect();
    let ow = bits_for(n_out as u64);
    let out_left = m.reg("out_left", Ty::UInt(ow), Some(0));
    let send = m.reg("send", Ty::Bool, Some(0));
    let request = UartTxIn {
        start: send.q,
        data: out_buf[0].q,
    };
    let utx: UartTxOut<Sig> =
        ports::instance(&mut m, "u_tx", &uart_tx(cycles_per_bit), &(), &request, &());
    let (tx_busy, tx) = (utx.busy, utx.tx);
    let zero8 = m.uint(8, 0);
    for i in 0..n_out {
        let rest = if i + 1 < n_out {
            out_buf[i + 1].q
        } else {
            zero8
        };
        let next = m.mux(send.q, rest, out_buf[i].q);
        let next = m.mux(out_valid, record[i], next);
        m.set_next(out_buf[i], next, None);
    }

    let pending = m.any_set(out_left.q);
    let tx_idle = m.not(tx_busy);
    let not_send = m.not(send.q);
    let go = m.and(pending, tx_idle);
    let go = m.and(go, not_send);
    let go = m.name(go, "send_next");
    m.set_next(send, go, None);

    let n_out_k = m.uint(ow, n_out as u128);
    let left_down = dec(&mut m, out_left.q);
    let left_next = m.mux(send.q, left_down, out_left.q);
    let left_next = m.mux(out_valid, n_out_k, left_next);
    m.set_next(out_left, left_next, None);

    m.output("tx", tx);
    m.finish().expect("bring-up wrapper is type-correct")
}

/// A board top for FPGAs without a reset pin: `clk`, `rx` in, `tx` out; holds
/// the wrapper in reset for 15 cycles after configuration (iCE40 flip-flops
/// power up at 0). The one hand-written Verilog of the flow: the DSL's `rst`
/// is always a port, so a power-on reset cannot be built in it.
pub fn board_top(wrapper: &Module, top_name: &str) -> String {
    format!(
        "// Board top for {w}: power-on reset, then the bring-up wrapper.\n\
         // Generated by cost::bringup::board_top.\n\
         module {top_name} (\n    input  wire clk,\n    input  wire rx,\n    output wire tx\n);\n\
         \x20   reg [3:0] por = 4'd0; // iCE40 flip-flops are 0 after configuration\n\
         \x20   wire rst = ~&por;\n\
         \x20   always @(posedge clk) if (rst) por <= por + 4'd1;\n\
         \x20   {w} u_bringup (.clk(clk), .rst(rst), .rx(rx), .tx(tx));\n\
         endmodule\n",
        w = wrapper.name
    )
}

/// The wrapper of a generated unit, its Verilog files (submodules first) and
/// the unit's port widths.
pub struct Bringup {
    /// the wrapper module
    pub module: Module,
    /// Verilog files, one per module, the wrapper last
    pub files: Vec<rtl_gen::emit::VerilogFile>,
    /// widths of the unit's data inputs, in port order
    pub in_widths: Vec<u32>,
    /// widths of the unit's data outputs, in port order
    pub out_widths: Vec<u32>,
}

impl Bringup {
    /// Wraps the unit of `g` at `cycles_per_bit` and emits the Verilog.
    pub fn new(g: &rtl_flow::Generated, cycles_per_bit: u32) -> Bringup {
        let unit = Arc::new(g.module.clone());
        let module = wrapper(&unit, cycles_per_bit);
        let files = rtl_gen::emit::emit(&module, rtl_gen::GENERATOR);
        Bringup {
            module,
            files,
            in_widths: g.ports.inputs.iter().map(|p| p.width).collect(),
            out_widths: g.ports.outputs.iter().map(|p| p.width).collect(),
        }
    }

    /// Writes the Verilog files into `dir`; returns their paths.
    pub fn write(&self, dir: &std::path::Path) -> std::io::Result<Vec<std::path::PathBuf>> {
        std::fs::create_dir_all(dir)?;
        self.files
            .iter()
            .map(|f| {
                let path = dir.join(&f.file_name);
                std::fs::write(&path, &f.text).map(|_| path)
            })
            .collect()
    }

    /// `verilator --lint-only -Wall` on the files in `dir`; `Err` holds the report.
    pub fn lint(&self, dir: &std::path::Path) -> Result<(), String> {
        let mut cmd = std::process::Command::new("verilator");
        cmd.args(["--lint-only", "-Wall", "--top-module", &self.module.name]);
        for f in &self.files {
            cmd.arg(dir.join(&f.file_name));
        }
        let out = cmd.output().map_err(|e| format!("verilator: {e}"))?;
        let report = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        if out.status.success() && !report.contains("%Warning") && !report.contains("%Error") {
            Ok(())
        } else {
            Err(report)
        }
    }
}

impl Bringup {
    /// Writes the wrapper into `dir`, lints it, and builds it with the C++ test bench `tb`
    /// (`verilator --cc --exe --build`, model class `Vtop`) into `dir/obj/Vtb`; returns the
    /// executable. The simulated boards of the tests (cost/tests/bringup_tb.cpp,
    /// bringup_pty.cpp) are built this way.
    pub fn build_testbench(
        &self,
        dir: &std::path::Path,
        tb: &std::path::Path,
    ) -> Result<std::path::PathBuf, String> {
        let _ = std::fs::remove_dir_all(dir);
        let files = self
            .write(dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?;
        self.lint(dir)
            .map_err(|r| format!("lint warnings in the wrapper:\n{r}"))?;
        let obj = dir.join("obj");
        let out = std::process::Command::new("verilator")
            .args([
                "--cc", "--exe", "--build", "-j", "2", "-O1", "--prefix", "Vtop",
            ])
            .args(["--top-module", &self.module.name, "-Mdir"])
            .arg(&obj)
            .args(&files)
            .arg(tb)
            .args(["-o", "Vtb"])
            .output()
            .map_err(|e| format!("verilator: {e} (run bash scripts/setup.sh)"))?;
        if !out.status.success() {
            return Err(format!(
                "verilator build failed:\n{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(obj.join("Vtb"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_unpack_round_trip() {
        let widths = [8, 16, 1, 17];
        let vals = [0xab, 0x1234, 1, 0x1_2345];
        let mut bytes = Vec::new();
        pack(&vals, &widths, &mut bytes);
        assert_eq!(bytes, [0xab, 0x34, 0x12, 0x01, 0x45, 0x23, 0x01]);
        assert_eq!(record_bytes(widths), 7);
        assert_eq!(unpack(&bytes, &widths), vals);
    }
}
