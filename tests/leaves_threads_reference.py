"""Induced masks of main before the threaded analysis (commit 87217cb), for tests/test_leaves_threads.py.

Each entry: (kind, layer, exemplar) -> (shape, zlib-compressed np.packbits of the mask, base64). Made by
analyze() on leaf_family(3, size, kind, rng=seed) with simulate_scribbles as in the test.
The spots entries of exemplars 1-2 were made again at leaves73 (issue 22: scattered marks are not
snapped and are read where the veins were removed by their mask alone); their IoU with the true
spots rose (lobed 0.78 / 0.57 -> 0.89 / 0.82, elliptic 0.52 / 0.77 -> 0.83 / 0.93), the veins' are unchanged.
Made again at leaves75 (a scattered layer's edges by its pixels' colour, marks the veins took given back
by shape): lobed 0.893 / 0.822 -> 0.898 / 0.772 (exemplar 2's 63-px spots gained a 7-px rim of their
soft edge), elliptic 0.826 / 0.932 -> 0.835 / 0.950; veins kept as main's (elliptic exemplar 1 now has
1 px less, IoU 0.999).
Spots made again at leaves85 (a mark's edge by the exemplar's own marks' colour and the blade's colour
round it, not nearer a layer above's colour): IoU with the true spots lobed 0.907 / 0.898 / 0.772 ->
0.907 / 0.920 / 0.897, elliptic 0.905 / 0.0507 / 0.950 -> 0.905 / 0.0504 / 0.959 (exemplar 1's
registration fails: its spots are elsewhere either way); veins kept.
Elliptic entries of exemplar 1 (veins, spots) and exemplar 2 (veins) made again at leaves87: the analysis
had turned exemplar 1 over (its outline's mirror image fitted better under rigid maps, chamfer ratio 0.58);
now registered both ways, it stays as it faces (registered blade IoU as good; true keypoint error 0.9 px
against 24 px turned over). The "0.05" above was its turned-over masks against the unturned truth; with
the truth turned likewise it was veins 0.734, spots 0.882. Now, against its own truth: exemplar 1 veins
0.737, spots 0.882 (same pixels, unturned); exemplar 2 veins 0.788 -> 0.753 (the layer's shared delta,
IoU 0.954 with the old entry); every other entry unchanged.
Veins of exemplars 1-2 (both cases) and spots lobed 1 / elliptic 2 made again at leaves93 (an exemplar read
with the training colour model chooses its own delta at its own ridge pixels, issue 22): vein IoU with the
truth lobed 0.684 / 0.384 -> 0.807 / 0.720, elliptic 0.737 / 0.753 -> 0.799 / 0.819; spots lobed 0.920 ->
0.928, elliptic 0.959 -> 0.945; every other entry unchanged.
"""


REFERENCE = {
    ('lobed', 'veins', 0): ((170, 172),
        'eNrtVr9vEzEUfi8++Q5xynl0RERvY8RdUIaovT/FVQeWSpyYwlSHIFg6dOTPYGR0VakTYu54SMwoiCVIhfCctHe+Ow8wIISUlwzV'
        'p8/vlz9/KcAudvFfRhpE7W9T8xB18Feo7CZEPbR/MJYJUZMgNZQ2Daa1RYjKg1Qdog5CVJMHwIQFwNPFsg++SjBwvDCiB2KQKjrU'
        'zTgYdag6SOVDR4U2tdinjYrN1xsdN63LNtVui7WzpmAHfWolQd1SoxqMGSFUiahpc42THBIqSA3gqklwRZsGu/eJ5NWIg9sNdU3N'
        'yUmNzuCrgW1Tb5rtGbaE7VaaWkcc+OC2/1mdVCmYabm5wbg+/wRN+hmNcqmWd/JCO8SFlawCUPsLU2/gvRzj+ie1yhNVL2t0CVa4'
        'rNIu6mWxoeYITkLXsqYW5RRKQVvMY3x9B0YcbeaoAyihkSd1YFxWnXlvKQVFS81Zim/RNBugv8VzKq9sc2OKyBhXcM2jRrMMjAbB'
        'aXwLqhFRwlwhUBKalxChmZakOlwkXlcg2RdHTV8Y730hHBsn0JOlb1wqlSA0sCvfDOK5uWDx2ijlXTd+VFyoEhjSCprzx6B45Nrz'
        'znOm0eqCUl74XjKG8ZAEb3npPywDuirggD5eKMEfRCQG9A2G7uqbLMpLbytuMWJUpdkqb1kJZ3gGNuNtjy610ilUVrYM8yxjQBC2'
        'bC+bW5myrhOWkizvpGsNtNZ0rPveqi5f9p2IjX0B3cXoQ8jdfpie5zCIl+35XTyCh+DeQZtqmYWn3REErm0kuyPg96z3cxaJm/PT'
        'nu0fHdyLDrtJ+R6cw6pLfWzuQzLrdQXvcN7pFSsaTO61OygoYY7zrN3UgSH9CzVtoc8Sp3cOEx+M7crpXaNfDJfZ1pBbcpl1gaaJ'
        'EBjt/iPaxS7+TfwCrp6XSA=='
    ),
    ('lobed', 'veins', 1): ((170, 172),
        'eNrtVk2K3EYU/qpLSFqUJRFvKtCMGnKBMoakbQ8ZhVwjC0HAXnogmwEPnmraCV7kAF4FH8HLrJxqNzibgclyFlloyAXau44Z6Lzy'
        'kFG9ki5g6FqU4ONVve9976cE7Nd+7dfNUqOoGwOTm8+Eo69vPi0Dv7j5/DJ2TRFdbo3fTzmYC7/LdURL+12bKAJ/oVhYhnap36uK'
        'BfDxE00pmOmpkf5jmGkmMaf9HTdtdGYhLl5zAsKeA/NSRsIq7+sHE0Ww9DyecTAFxaVWHUdb7/s0ZZ6Q+YQJ24Solm8ESaAjUlf4'
        'Forzh5rrdIaOm+JC2HcQy4KBpVPKkNY8Wydwa4hHUdVYlVfqXreyPC/tYrHMzrkzV9Cds6drzgtGvJ0kdaTrErWDO4t0NdlLqJTX'
        'G1Y/d064JtJ1fqpQv+Bgc/Zb68QbbiqziyWMicKqXGeIRET1kqyKWdkDD0gi6Svra2x78jufQsqe6PK+gbL5jHSZsbZzMO8pXVKF'
        'bafSSeqo3L+xyHtVXNue+Px3ifinN03SO56jRnu3u+Xq3Hf2wJeBlNOir0mViy0mc0zN1a2zzjl82eDArR/L328b4DzHvRRZor5y'
        '9a2vemHlBtI176cB2SNNdQmT6NbpQAALQ7x+fKFlr2B1TVJpTDbCHvfqE6cZtc8hTDBcTNlN6IYMkrXKn26WQvzFBkaryH8jPth0'
        '04MTqrUmwbXG90ENmxyeurCqCPvK4qGqKCthrisK5pBqenXJGwu4rjClAqiDHiTFPiDrDiGCGtimeLLB48kxgj68Q2VRWrQtpTao'
        'gqluDiATNnyVXCReFccLxpgGW/krYes+XpEqKowHFk25C/RuNsjWl0jLQJkzRf7LI+BpAGYbS8f+2KC+CqN9qVPkz7HrwvFYr2wn'
        'lrudFmxivFLISwqVTdL6X1J7Ay3YIKmvgftkWrPWyrazhGZONLSyHegdWG55G5ZWa1RH8esSDXf2cETrACOm8iofMf3peORFLB4m'
        'Q1CsmnaIniAdgr4Ihuf/jh/YT+dpSAz5F5BD/rZFNUC3GYa61DZ+NPz5V36ex+ixG/lTKIoR08EQ/r89RqTe/33t12e7/gOxysk+'
    ),
    ('lobed', 'veins', 2): ((170, 172),
        'eNrtVsFqFEEQrd5eewZpdwcU7EPMThC82iLoBiQ74I90yFXCelJEk04Cm4uINz14yCfkEzoJ5JSPGMlVcMDLgsuONbsbUrX2XYTM'
        'YWf28bqr6lV1VQPcPDfPP3tEDExtDP0VA2UZQ1vMhF98OLquv/hoU+rg6oPuKsL8HbqeoPrq9YlusDDhDI1AycnMKeGZk262b5/F'
        'Kr7NvbtkzIXhrYqh83+6w0A1f3nH0OHsN2vnFExgbvqMCifGcy/TNYLm6yPTpErsZ4Sq7nxHag6rW0yAsWm8EBs5dUoBBluA3WHU'
        'oW4EbMmKZk42entwkqhVGNsNoMU5GJpDsTdFBzqBCTs073P09QWjKphKtCU8pYrQbUilyVK6XlZIknuSatWBNw3V2IyiR8rNAmBF'
        'nAGulAFcxsscxb4ExVxNm9rMViBQVzF2A7eg6kIgYBuSQyik94qVkPhZGtgwrLQVGEyiegcsAvtIowsnFVew550Eo4C5NUAjrskP'
        'LU1xBE410bJdNcyoIXM8AqtwW/Fx6ayCtcLrwEDdFwlswJhTN33m5NuEYVmSQheelkN+0gceJuo+kwVNX4Cu/AozJfZR0cOLJVMr'
        'NgXTKyQ/m2dQCN8H3oc6rmWs5AKAmMLzAyQ6Fv+DsSytYn1o1yeJ7zdyEa96NZ5U4Z2mfUj4GilGI5F6JcdNyYYUWA3aWRaMb3Gl'
        'MYSAHSLQVA2xE00xYZpgAYUbap5q9MZJif2hzQ4bVoVtJKGiYumVifAS6AkSddCQG8yCJ1xZVwGrQnhDO9bregLOIpUKqPq9Usk2'
        'hJxq/RIrs3ROY31fS6DQ8XqEDjtBZgkuG9XhtCkKf61WDtrtaod9N5V0VIygPpcYgLekN2VFOnHrLTCSV7afyGOs4pyd+ExWAwm/'
        '6ykfbA8vy8f1l/p6mFg7mwa9CU2hPG06XFL/YG3ktmsOfe8zPy07mBIvTtq8BLFcNDzLinxpPmDKNtut5eHYh9PM5ctzFMwT9fcw'
        'lQdN71t+XGw+66XxtihlE6HaGFWGNELdhghV5zpmKrK8inn64SBCVXo7dpN4NYyAyX7MVvTSoqK3nuilZTWCtcVxBHVPYpbUvQia'
        'hyIitYnoB3ejCazyCLUXi198jUW1FmKojsoSbu7D/+vzB2fcw3o='
    ),
    ('lobed', 'spots', 0): ((170, 172),
        'eNrtlM0JwjAYhhMK9iLt1UNoVnAAaVdxkKIdxGHqAuII3nq0NyNIY3L9fAYo8r2QQF4evr+EGKNSqVQq1X/pQWZ1FEY+dzdhtmmV'
        'bxGgyOfYCrQbjakniS5p62eB+kxthGkXKtNj8f16hz2SuSXTInogs0T0Z2D7PDA57GJIqaJEQ1o7OVufUOOEWQeo1cYBCnIB26Ti'
        'Hfb5JLT6EDrho6b8V3pC/k4oZmoavBKKak+Evqgrj0Fncs+Uqrzox6ZSrUtf6kssmA=='
    ),
    ('lobed', 'spots', 1): ((170, 172),
        'eNpjYBgFo2AUDBvAgU2Q8QA2URlsgsxYlcphtYsEpQVY7RqNrlEwCkbBIAAN2AR5HmArTN8Rb6o9NkH2H9hE/2MrTfn/YFNaj81Z'
        '7NiVYjOVHZt+hgqsRTTWcDEYTS+jYBSMAhgAALumDy4='
    ),
    ('lobed', 'spots', 2): ((170, 172),
        'eNpjYBgFo2AUjIJRMAqGFWDBKuqATZAVmyDzH2yi9QewKf2BTSl7AzbRGqxKsZnKYINNkPHAaNQOdfACmyAb1uTih02Q5wHRSXsU'
        'jIJRMApoCwBLjgky'
    ),
    ('elliptic', 'veins', 0): ((204, 198),
        'eNrtl79uFDEQxsf2ancLK7t0lnLKLX0kjGi2OJ32UcyfB7iSLk6QoEEKJXQ8iqMgQcUTUNxBj47uihT40ubnIlIKkG5Kz92M5/s+'
        'z8yKHOxgB/t3bVtyrEuOVDg3pT8clRxPCufNez6faj5X0hcCDRM73FUh9XNbSBE9h6rlnAFptYro8E4XgA2c3Cjv0VFZ4Uv1XnGK'
        'kBhCdSEOHdpJQIcNBsuLSrAKLRVLqhXPyvE6jozTESNrZGQAKwmYenDKlJhYcIb49BNnkB+nyIQYlsck84LQwitEsFbnTjwKzQ4I'
        'yGA9c5H6SKw6JS/wFYdKfUR9xNdmon6gZWjw2VuJMxRU1gDLIFU5C755p9VnJrufJaQiXm1IB8GYLhqiwtpfMqPy+qWluts9tjX8'
        '3uc+AeS1klQvQF7GopoIwQzHschvUKaTURoH/SlIaEdiO6r4CHQTamnSKcKRS0gBUvT8Jq0ELSuQ4GA+uAZ1cBzDyrwBxxfVpWPS'
        'oOv+SIPyXxgiT2STCyEdqLc8q7Ymj5cVTJdUJUzt9hwtIdLjuOPh9r1bywjVqfUz6ai4Rmy1Iy1bGc4SkbdSl9fUl9W6WVtNTzUt'
        'ZNlim8gJ/N0kodlL/yuI1ubSzBZE22cNdDRUX+IGkqv71ssJZPBqPTWJuqk5lx118mSrM5ieNjei+YZ0Vss7XJZ8W9/wsPUn+z5F'
        '42V7OzLu3vZiEtplGpMBjHDbqp5En9Bt5xI76oJ+1GqHtw3dTxx5191Ni/Po8kYG6vF6IaUlquCwpQ3RlxyRVHDb/c+QDOPnO97f'
        '0n231nlpZU4rPtelSP19V+xipPbBvgceLtLBDnaw/9T+AlyJf2I='
    ),
    ('elliptic', 'veins', 1): ((204, 198),
        'eNrtV7FuE0EQnb099g60ubsKNuAkhyJBexApMtJhjoaKj1grEhWFSyOhMLZRkiKgfAAfkU9YA6JKQZkiEhdEz0k0RrIQ19/bggYo'
        'PKWfPbPz9s3bMdEqVrGK/zPELw+gnAeQvlTaBxQ+oPLUEL4a4cADmCPPWW0OgViwhUCuiCGwNAKXcPYmJlDwU1xbEa5dGIFr2zzE'
        'PE0Yc5sGGmd6Fl/DmXRuPMzyEgP3A/x9cYYzWdPgtt3jGZSIoEATUoiiuIDFtbxcwOKFOKsreChZzCAfbm0K9RzRLr69fWpEjfTx'
        'RroUAVSmDt+e3WF8e65S8PtiQqhtwTKk0z4ai8SoAgCqev4ys6C/RK7X8wmc7UEQIKYsjU2Mhs+JeoF0HtHabIR0vktfjQVMidek'
        'hwwEEhraUZGDp72IdxjqYJxPoUWlIxVDgfQqaEZXTiydg895e8IKdneo2qHpnnbcXhLVgClHPasuu6eVJ/SQHwRZl1lLm7HT3RJp'
        'K8I7BOyrZ6kYIU19IZozGMqgJKkJ9TciPQJnIvpGPyqNLqkRL95dh5SL924EAaUFnmJDMZwLZ6nfRRISc5aZAU3IT2TyopuJbn1n'
        '1xVh1PK0UOCtTElKh6hNcpaSALUbB6R7iNqyoOwcOecF05Ni3s0kN2myCN4Czy5V1EhkRgPTc3CSttxt3kCTtEUT2oNv0jSWMQSO'
        'c9O1nCCkqHaX3b6TjIxTwDoHVTWke2BgUilCycCkEh2aGNl5ao11aAlJeXhAfQTQtBAOAlc5gS8Jl/glibiOoP3fmEGbj+nDMSxd'
        'bMvP8AVtRV5bUEN8JHnYGk8XaEj1I0YTFq67PlyLtpYS6UNyVJd4WCXsogV0gpeWOqvxbtLsefbEn6d4X6JXswYCXO7DX0T1XfxG'
        '03jhqf2I/3RxzryLs2+b95VQvkzGB+Q+gP/C/4LV/7JVrOIfx2+mFacN'
    ),
    ('elliptic', 'veins', 2): ((204, 198),
        'eNrtVz1vE0EQfeu19k7iOF+5UUxsiT9wIUUOyXIsReJ3LEobRUuFiwATgUhjiZQpkPgLlFRok4IqP4Hi6BGyBIULRFi33NuC1B7J'
        'zY53Zmfem48DNrKRjdxJqsR5PUsoroSf637iQlGNuWKQMjUyKVM2oTi4SChWLvFaftxHwRUWdSJPCFwREi5UnnBh3EEiOPzmli57'
        'HL5inIPHHcbqhpoS0fSG7iGjlsocHIzjMc+ItvKcnTs8wh/2pIC5WlDodFuwuA22xHHwnugEeJYH4eBaqnij3nI+1YYTJJMtoSgV'
        'OAZFyWYtp2edRcjpa21MSfe4p4Jj6Kl+poShZ5b72S1Db6AWD3LGA9sbOjRE4fFYFOPBNaYwlMyY0xrTAU4JhVvJgtIfRid4YDNo'
        'YmsZU5gVrCSVhCmxVQdj1Adi6UxsjQl5kg5HQuCuUKr3DG6HYeQBASmg2VHSkr6CpS+IJTM236QilgbY/QIhIE3U2aUxtCx0axlI'
        'IfL8GXuUoMT3QddHJJNV7d7Hbl+JXjSyQMBTMl2ru0Vs1FdGHYd5WTMShqz1s5L0lQt1jq6lcjYKZo4uCUdyEn8Ydhw0uohsJnA7'
        'M4xmCEihmPRRW5LAqqkQAhtgddCGlsUtTJ0TDpYT3COJmsD7qumGp1aR/SF066L0Wusd7HZujF1RmHbd2P6VSJsR1JJ1+fBLvRZS'
        '9npgt7upxbYUvr5pu4V0KPsIo27KdYbVuiF1Uz6IvYWEvcDJfSGLgF7q4cMYCiPzC2GdtoT+DEbNIYpGs07UwLn+lDXUp0q2yOxW'
        'P43JT8mA6a9g65Z0zjo21B+sB6ugzpbstVr6cfTQUWw9of86I4eCGTkuVcMmaJkXmRhPerkb2tioyI6IJtDJY7EHOnkanNK3xoj9'
        'jE57jys+7SP/fc4UbZGBmmprP6CLVzgXTxXXc7p4Veodv9DoTxndp+da5jSKxvAL8LZJrNNHiWX38cGSK17dJm68TH2QJP6f2tiR'
        '2tiR2tjTLtR/uxhvPiA3spE7yl8rEqzE'
    ),
    ('elliptic', 'spots', 0): ((204, 198),
        'eNpjYBgFo2AUjIJRMApGwSgY9uABDnHmAzgk+C1wSNjjMIrxPy6TfuCQMD6GQ+JdBQ6Jybi8Yd+Aw1F/sIvL83/ALlEhPwObsAFj'
        'T00CNi8cYDB8gs3eZwxsh7E5lv0GgwQ/NsfKA7EdNpP+AQlsjmUHeo0Rq0k/SIw5BhuSU03DaI4aBaNgFIyCUTAKRgF9AAAkiRxI'
    ),
    ('elliptic', 'spots', 1): ((204, 198),
        'eNrtlD0OQEAQRrGFDq3GGZSO4xSiwgEcyjGUKrWoSdDPK4go5HvJNvMy2flJxvOEEEL8iZ5EAvGAEjISe2fHw1XjF1/gk4hI5CS6'
        '96oqqVr6IxxAtJDhNkhwC4mJxCd7ogbj20enpiHO1GBhBNOrKGsk1VWU9cV4vsY6m+e2XX1n20IIIYQQDzkAc3wRKw=='
    ),
    ('elliptic', 'spots', 2): ((204, 198),
        'eNrtlLEJhUAQRO80MPsaKgg2YfAD8azEOgwELcNyzGzDzNTQ4AduATPpB3EeXLLDMsfs3jknhBBCiPcQMaFciDDsuO4PIiRhxULx'
        'IxbpSYSJ3XZgwv78EeVMsJQ8ija2YgXjs44RNdjoPEoqDXaQRX6ZxYyGbcUeebd2vmht2BL48y/pXsyeLK2rOyJs7Ik1zIJ5f9hl'
        'M31YQgghhLgBZfkaZw=='
    ),
}
