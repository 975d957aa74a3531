# A stand-in for M&C software that opens its controller as pyserial does,
# through a terminal server's RFC 2217 port (docs/simulator.md):
#   python3 docs/examples/mc.py rfc2217://HOST:PORT
import sys

import serial

port = serial.serial_for_url(sys.argv[1], baudrate=9600, timeout=2)
port.write(bytes.fromhex("82 b2 30 03 03"))   # 30h Device Type Query, parity in bit 7
print(port.read(11).hex(" "))
port.baudrate = 4800                           # SET-BAUDRATE: the sim answers 4800
port.close()
