; G0: a joint move to the pose at the program's joint speed
G21 G90
G0 X0 Y220 Z250 A90 B0 C90
G0 X40 Y200 Z220
M30
