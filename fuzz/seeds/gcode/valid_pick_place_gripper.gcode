; Pick and place with the pneumatic gripper (M5 open, M3 close), an operator stop and home
G21 G90
G28                         ; home (standby)
M5 P1                       ; open
G0 X-25 Y220 Z250 A90 B0 C90
G1 Z225 F1800
M3 P1                       ; close on the part
G4 S0.5
G1 Z250
G0 X25 Y220 Z250
G1 Z230 F1800
M5 P1                       ; release
G4 P300
G1 Z250
M0                          ; the operator checks the part
M1                          ; optional stop
G28
M30
