#!/usr/bin/env bash
# Installs the tools the flow runs: Verilator (simulator of record and lint),
# Icarus Verilog and Yosys (second compiler and synthesis checks).
set -euo pipefail
packages=(verilator iverilog yosys g++ make)
packages+=(nextpnr-ice40 fpga-icestorm)  # rtl-cost: place and route, bitstreams (scripts/fpga.sh)
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq "${packages[@]}" >/dev/null
verilator --version
