# Section "answers" of the third audit (issue 35).
