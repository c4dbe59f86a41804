# Section "urdf" of the third audit (issue 35).
