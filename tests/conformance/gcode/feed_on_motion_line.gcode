; F on the motion line sets the feed
G21 G90
G0 X0 Y220 Z250 A90 B0 C90
G1 X20 F600
G1 X-20 F3000
M30
