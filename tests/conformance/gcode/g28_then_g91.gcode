; After G28 the position is home: the incremental move goes down from standby
G21 G90
G0 X30 Y200 Z230 A90 B0 C90
G28
G91 G0 Y-20 Z-60
G90
M30
