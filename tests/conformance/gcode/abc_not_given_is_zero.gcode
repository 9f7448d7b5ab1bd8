; No A B C before the first move: they are 0 (tool down), as in the official parser, not the start's
G21 G90
G0 X0 Y220 Z250
G0 A90 B0 C90
M30
