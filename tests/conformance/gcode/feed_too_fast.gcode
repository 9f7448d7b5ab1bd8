; 30000 mm/min is 500 mm/s, faster than the PAROL6's 200 mm/s
G21 G90
G0 X0 Y220 Z250 A90 B0 C90
G1 X40 F30000
M30
