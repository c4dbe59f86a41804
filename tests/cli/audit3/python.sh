# Section "python" of the third audit (issue 35).
