# Section "freedoms" of the third audit (issue 35).
