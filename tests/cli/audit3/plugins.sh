# Section "plugins" of the third audit (issue 35).
