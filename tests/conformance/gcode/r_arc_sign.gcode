; G2 with R > 0: the arc of at most 180 degrees (here a quarter circle)
G21 G90 G17
G0 X-10 Y220 Z250 A90 B0 C90
G2 X0 Y230 R10 F1200
M30
