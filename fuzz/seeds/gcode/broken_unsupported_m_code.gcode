G21
M8 ; coolant on
