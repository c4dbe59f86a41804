# Section "numerics" of the third audit (issue 35).
