; G91 after the move on the line still applies to it (order of execution)
G21 G90
G0 X0 Y220 Z250 A90 B0 C90
G1 Z-20 G91 F1200
G90
M30
