# Timing constraints (SDC) for the FPGA bring-up wrapper on an iCEBreaker (iCE40UP5K-SG48),
# top bringup_top (cost/src/bringup.rs; pins in icebreaker_bringup.pcf, pinout from the board's
# documented icebreaker.pcf: clock pin 35, UART RX pin 6, TX pin 9).
# nextpnr-ice40 takes the same clock from --freq 12 / set_frequency in the PCF (scripts/fpga.sh);
# this file is for SDC-reading tools.
#
# One clock: the board's 12 MHz oscillator.
create_clock -name clk -period 83.333 [get_ports clk]
# rx is asynchronous to clk (the host's UART); it enters through a two-flop synchroniser in
# uart_rx, so no timing relation to the clock is meaningful.
set_false_path -from [get_ports rx]
# tx comes straight from a flip-flop of uart_tx; the host samples it asynchronously, 104 cycles
# a bit.
set_false_path -to [get_ports tx]
