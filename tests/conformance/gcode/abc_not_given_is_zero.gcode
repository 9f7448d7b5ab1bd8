; No A B C before the first move: they are 0, as in the official parser (not the start's tilt)
G21 G90
G0 X0 Y250 Z300
G0 A90 B0 C90
M30
