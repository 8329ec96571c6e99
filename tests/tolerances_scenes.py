"""Accuracies the scene tests ask for (the step follows from them; the error must stay below)."""

#: analysis.accuracy of most scene tests: max |simulation - exact theory| allowed.
ACCURACY_COARSE = 1e-3
#: analysis.accuracy of the test with every effect combined.
ACCURACY_FINE = 1e-5
#: A theory with Q off by 20% (60 for 50) must miss by more than this: the comparison can fail.
MIN_ERROR_WRONG_THEORY = 1e-2
