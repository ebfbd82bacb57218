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
        'eNrtVrFu1EAUnPU6tpWYO0sBZKTT+SpEaSQkEhQRi4KaD6CwhARlDtFEIiIbDiE+ISWfkBLRsCYFTUQoU1D4/sB0Bwo63prEt7t2'
        'RYd0W2yi0Yt3dua92QDLtVzL9a/L6UTzLvBtF9gTFpCqbc8CWX1UYYIyVnuUGmAIqeoPzM+WXv0j0jH3V02TM6N0L+U1C6PU59ig'
        '/bVZitgXYF9HJgEmTmhf4ybX0FVnPU6tG0wUj5cm6EHd66A00ZE6e+CZoE/XpQMz05EjRhIEloJT3L+QUVNgI/ZGqI/T1ikTn8F4'
        'zwBXZRimiFNpoBHkMdh6aH5AhEGE22UhTF/yA+H4JyYv0UMcjXaOhd0DHx13aOk6wbUMct/SNXUFQksWFCvvwWRm6bpBXZW4Vun+'
        'kIw5skr900lN2XKrVIwsqlld1V8Am1INRa62akF+roaCaLJSE8C/NSKfRoZZEulDspQHwELr0HM8SWrfNUvzfLdubvqq1mjelbo3'
        'gfWs4SolE9fr3/igMTYIQ7BKlbrptDmslBI3qNWkvMk/NEzJN2oe3w15ljRnJTRlY3CZyasa2e2Y+hKpG18M6F8BfgtyVeCJiPlC'
        'weicVIrhVEw8akDOZhjR+GxBb4DILx0CfHBjVL6ojX0zAiNXlmS4LbxKzyli6KrLPrDDRpLeoR02YUT+615HlAhblEDFmTntFBkR'
        'BnTjRAsGusVzrJRboLs0peT/swpPnTG0HKG5UIbluTCsHQQYgrswuoAxF3egZlCjK9M0w4y/IazQGs4jb8WmQNafa3fIKvDjM3h9'
        'TZl9l7q3vw3saKBfCeL4qUIy1W/7LvYQvMK81OMxKUSJyY95bMSLfxiquWDCSNK1n1L1XMyMIEnOqVup1Ewif6YMiq3Q9eeqBaxS'
        '9EUUt/KtFe6XkkUd4BAdpXwadJS+GMuOh+ye2wZZkXU8hbvw2mBfdLya7HvXA7srkbb5r4K3+Ysc7cvOfLR1SUTrJaC/P2wnHjCW'
        '7XDEaq+jtBXCl+PRIfXyf6nl+m/XH8gipmo='
    ),
    ('lobed', 'veins', 2): ((170, 172),
        'eNrtVj2LFEEQrZqe7R10vBvwgsGD27nsAoUBD1lQlvkBBpcJRg2mImtmINgiGIkYGt5PuNCwz8BfIXJgYGIw4Qaya3fvrHR1V7CJ'
        'ILgNu/Q83lRXvamPBtit3frHVsuBNzlQXHFoFj6gHjZNCJ5w793ZbFRI7YbNXkgtNxsdohtqTZ2MHCFn0FgPyBvDuj682BO0Z7wC'
        'yQQAMOeCHXMy44vIS78KXTMGbqypmSJBLdbUGXFKDsq8DNAG5msRRR9+OYFmvdOhrO0+Iyy+/pYKq+oHKVXCMv0GaPaZqOaiT0EJ'
        'jxhqI9VfK4EKwKR5rSGPU6iCWzS1fQro7DFNotb/LudEFlGDQqhyquBMS2e5I/mB9jRbVkWUmva0xnmq4gLOoMJ3EJdBizqnYeVT'
        'a7qBT5R6rKHBYkzBUWGplaooetvakKOc5qur2Qt9QFIZvbsP4UNacIe0YwzSt0RWgGudD4IKgHtw6qgdLY2pbUySWH2iR1JPo8o8'
        '/KGVE7+kDetK+/SlSmULl7JcqyyTKnaORtQczkDiDGgTM1a4s5J+PVVaJxGo+gK1jeYk6hmzGs6tv5EkK1O4TKkhVEWseiN9AYaq'
        'PF+cOkUoVU4nPosN0doSxHnngi1osl++LSApxPy7+SyTAlKvSqXSabH8wpXgT5V0cru+ZhUkPVL0d21Dvr+MUKHG78UqHlG/SBvc'
        'dONF5JR3cxIddEQG0h+93f+92KJrY3yD0hxYc0NXvOGoiqOW3OBAdnC0yB3FevWMA0sORL31TSLjwJyV6ik7Obc/SrLNnb20HLFR'
        'XXDoMXtUxaGGM1pvfb9C9uow4QTAj6yB3W32f1i/AeV6Z5M='
    ),
    ('lobed', 'spots', 0): ((170, 172),
        'eNrtlM0JwjAYhhMK9iLt1UNoVnAAaVdxkKIdxGHqAuII3nq0NyNIY3L9fAYo8r2QQF4evr+EGKNSqVQq1X/pQWZ1FEY+dzdhtmmVbxGg'
        'yOfYCrQbjakniS5p62eB+kxthGkXKtNj8f16hz2SuSXTInogs0T0Z2D7PDA57GJIqaJEQ1o7OVufUOOEWQeo1cYBCnIB26TiHfb5JLT6'
        'EDrho6b8V3pC/k4oZmoavBKKak+Evqgrj0Fncs+Uqrzox6ZSrUtf6kssmA=='
    ),
    ('lobed', 'spots', 1): ((170, 172),
        'eNpjYBgFo2AUDBvAgU2Q8QA2URlsgsxYlcphtYsEpQVY7RqNrlEwCkbBIAAN2AR5HmArTN8Rb6o8NkH2H9hE/2MrTfn/YFNaj81Z7NiV'
        'YjOVHZt+hgqsRTTWcDEYTS+jYBSMAhgAAB6mDw4='
    ),
    ('lobed', 'spots', 2): ((170, 172),
        'eNpjYBgFo2AUjIJRMAqGFWDBKuqATZAVmyDzH2yi9QewKf2BTSl7AzbRGqxKsZnKYINNkPHAaNQOdfACmyAb1uTih02Q5wHRSXsUjIJR'
        'MApoCwBLjgky'
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
        'eNrtV7Fu1EAQfev1rZ3Isa9jg47gNNAaIkUndASLgn+g2wgJUVBceQUKk1wEFCnyCfkMyg1QUCBBGaQUmz7FlUeHqf22QIoQxU15z9qZ'
        '9+bt7BywilWs4v8MtYwAiY8AOnZUEQOGMaCN5FCxHOmjWIoPkVpdTYFciaNAbSAUuLaKp/BunQJGCVckT8BzN1bx3K5OuU4iDQWqJOUn'
        'vcx5saqoLVfWyhsOPEz49+przknki5YCXs3BaCgkBZhDDPIm4V29WlIajfoWaHKnmzkvaoN3L8Mu794BFiowFifaV7QZk8rz7rmdiAd9'
        'a6hn1SEstYdOwfqqUVoMx0zZ16+GLeG3rjeDP2TKYi9JmFIOM5vXtN1hyXyeYTCfMp/vIrGOKKWOUThhBrHYSQZCq73MH3AfzHDEr9LU'
        '8Ks3arcYMDh1uCC/iz4UQ9llpiu4T2P2p0mBKCUYOXPVr1YLHss46U/bzOF27tN+iqoz4T2QiTBq0UyZp34C58Iu5QS6AOM3RTGlwgbs'
        'tPR6L/CcKqW8+oQpBQzocFbeImeDpRvaqPtICXUumvBuoJ92Pzf9k7D5vSPh+2ZGe2HIW1lBJZ5JW9bQ3ed9Qe4IihGTdtJg+INNzkvB'
        's5oYR29BfexIsu5lCzqD9+zIZ6xJW34bG+yK3e38SQdkdRRZHapj8LcnCwj9gVAOYb0ho3OvxT62Ce9O81SzcV4itTmrtnLWeVZtJfvv'
        'MGYAjhrlKbAmJWUnEy5UJoELdWtOhcrx+YSmbpQ+pS/oOXRwGbkYX6Dfd4OnDyxgxpmwG5au+TFdi6prLXRwZmHCJ6qmLLocRcmXljAM'
        'fDdZvIjsib/OuAXxdk6PqmRywL3p7vM3GrPYRv1Ebm5xjm3zsRQmdpKNAXUMkBv7X9D8Lb1VrGIV/yp+A0whkh0='
    ),
    ('elliptic', 'veins', 2): ((204, 198),
        'eNrtV7uOEzEUPV5HdhDezJSOCJuIhtYLAgYU7UbsfyBL21BEq6FLgcChYCmQ2HILPoISUZkGUVDyAQM1QpGgSIEADyVzXGTr3HKu5r7O'
        'uQ8DW9nKVi4kZU4xy3wXIaPobepCx4xijE1dHOQU68x3mXNguMLCccUEmSxixoXIuVCzw1w5fnFL5zuZLCb9TNpxIj5xUIP0tE470NTS'
        'oJ9qwmSeqYi04Tr77nEDD1hIEQ/FSwqdbGgJFYaBJtHHfQ6Gg+VJeHgOaxDPOZ+c4gTRYRhoBxjMWz+EaqLh9HQJiXMarU0loah6hp6A'
        'Sk1MElfxlv7N0NtF/yrlgUXPoyKKGpeCYCWMuJ2AIkGdYUF7TEZ4OnNUyo/xI1VWcTJbWA1JbK1SCTXhVC95jgfElotKYUwsLYN1mJK5'
        'IuNxIHCXMOI1g9tjpBsGUkS1BzQEVaxqZklBfaFwF9j/AAb3FMtzpWhbSG8dRVWHR6Fhy2KAb0XXh27RaG6+6c6V5EWy1WCTsXututvE'
        'Snxm1PFYDCaMhFE2dddSmitn4hRdS4NZEdWCLL4xTloSjDoOKmESmwncXo2SGQJS7E17ICCJULqSgST/rWhF2+Ir2DAyGExxGQzu2rEm'
        'FuvE/hi7u8TUUsg97AdScqOadrD9Lw3cGGLFpnz8yXpSRllYUlpcCaYuCf9xFO60nO6EJHV7BXQLEk2RZovohvQCJ7uBbGm5kuYaa71E'
        '5seBzccB5DvmOuVlKjqJKnhPrxknRBh+JCD9SIjP2RGwhnUNmZxlGqjfGXNEFMsVi1aGniaFaklY1gyjZP0okAtSp1athGKFMjpQ0vqR'
        'JaC2vVfN6OZJuxB081Qp0hG/AuoZW59pib1X/DyQsqYnVmM0qKnG1QU9vOJpqKni2YIfXuIV/8GKt5qe5rUMC379KP4DnK0y9+Nx5vi/'
        'e7jiiqd/Mufxk03fHTL3g8kpXE6Re3eIjV1Mtg/IrWzlgvIXgOWX4A=='
    ),
    ('elliptic', 'spots', 0): ((204, 198),
        'eNpjYBgFo2AUjIJRMApGwSgY9uABDnHmAzgk+C1wSNjjMIrxPy6TfuCQMD6GQ+JdBQ6Jybi8Yd+Aw1F/sIvL83/ALlEhPwObsAFjT00C'
        'Ni8cYDB8gs3eZwxsh7E5lv0GgwQ/NsfKA7EdNpP+AQlsjmUHeo0Rq0k/SIw5BhuSU03DaI4aBaNgFIyCUTAKRgF9AAAkiRxI'
    ),
    ('elliptic', 'spots', 1): ((204, 198),
        'eNrtlD0OQEAQRrGFDq3GGZSO4xSiwgEcyjGUKrWoSdDPK4go5HvJNvMy2flJxvOEEEL8iZ5EAvGAEjISe2fHw1XjF1/gk4hI5CS696oq'
        'qVr6IxxAtJDhNkhwC4mJxCd7ogbj20enpiHO1GBhBNOrKGsk1VWU9cV4vsY6m+e2XX1n20IIIYQQDzkAc3wRKw=='
    ),
    ('elliptic', 'spots', 2): ((204, 198),
        'eNpjYBgFo2AUjIJRMApGwcgBTLgkZGbgkKh4gF2c8TkOCXb7A9glJP/gsIL/Aw6JelyurcAl8YBUfw8+IIFLAhhKjNiClhkoKI81+IA6'
        'arBpAEYdI7aQ4rcHYmxWSPwAWtGARcIdKBiHzW47ILbAlmxwJQJGXImAoYGaofsDl/U4Ei2DiQMOieO4kpoNLitw2c2Hy7ECowXWKBgF'
        'o2AUjIJRMAoAXTAbKQ=='
    ),
}
