; G1 F… without axes sets the mode and the feed
G21 G90
G0 X0 Y220 Z250 A90 B0 C90
G1 F900
X20
M30
