(Zig-zag scan with incremental moves)
G21 G90
G0 X-20 Y205 Z235 A90 B0 C90
G91                    ; incremental from here
G1 Y30 F2400
X10
Y-30
X10
Y30
X10
Y-30
G90                    ; back to absolute
G1 Z250
M30
