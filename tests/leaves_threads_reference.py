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
Made again at leaves94 (issue 22: the training leaf's thin vein layer grows along its fainter
unscribbled lines): every entry from this branch's analysis. Vein IoU with the true veins, exemplars
0 / 1 / 2: lobed 0.778 / 0.684 / 0.384 -> 0.845 / 0.748 / 0.522, elliptic 0.691 / 0.737 / 0.753 ->
0.843 / 0.756 / 0.800; spots unchanged but elliptic exemplar 2 (0.949 -> 0.945).
Veins of exemplars 1-2 and spots lobed 2 made again when leaves93 (an exemplar read with the training colour
model chooses its own delta at its own ridge pixels) was merged over leaves94: vein IoU with the truth lobed
0.748 / 0.522 -> 0.774 / 0.658, elliptic 0.756 / 0.800 -> 0.774 / 0.814; spots lobed 2 0.910 -> 0.897; every
other entry unchanged.
Veins of exemplars 1-2 made again at leaves97 (the fainter lines the training layer grew along are not
snapped onto the exemplars): vein IoU with the truth lobed 0.774 / 0.658 -> 0.775 / 0.656, elliptic
0.774 / 0.814 -> 0.775 / 0.817; IoU with the old entries 0.989 / 0.907 and 0.951 / 0.959; every other
entry unchanged.
"""


REFERENCE = {
    ('lobed', 'veins', 0): ((170, 172),
        'eNrtVrFu1EAQnbm11g5ZnY1oNsLKmQZKlgaliBIXlPkIRyloImGoLhV7XESaFCn5DOgo93RSqog6pSWokRHNRQo6xifF9tpbQEGBdHPSyXp6O56defNkgHWs478M4UTNH1MzF3XgpCZ/QZ07QHYbOdD9mXbVKl1p3dTA2QFXscJZrEn7mBbccTw1WR+9EgMH1eikj74QrA+Gy2nZR0+DB31Qplr1QDwNsE+NUm11e3Ud5nWoGVA+1aXyIWXl2zY1PaGOqsOFRRVYCqJKm2o4JYZHWtrqM1UNK2pDL2RVAVZUXtN9Rghdgf7iZuQ7CeUQCBLCxb06waVHYjejGw1fdVHfwIwDoi4X9L7dmjpmPyZaR9UIzmpwQ7Nyp+oK0szuwEMOnGHVFQnjOqlSMM5kddz49fnnaMQ3rMbCsTy4G4kZ4tRIRnNVz8503azPMsblEpDxoJ6j2ZqDoaKEkmZaN4sNM46Q4BSuZU1N813IowF8THx830wLTYg6GQ4gV7U8U6qArlpkWdjaewEqQnjMBH7Auq+o6fn+G5BGmWa4isjoF3DNvUazDHQGEQefet4IkXrCVlKSMGgpQ+/mpDqcBtAsTSrZ94oqTnRrv1Af6Uqgx2XbuBR5QJQdsMu2cfkzPWP+0ijFGi/AL4pHagwMIW+dP4Ln3KO3Ba3znGVospRSWl4SQzz0aGw8by/WRGdFCnv0a4WS/KFHYsC2wdCsfsr09Rys9czUViFGi8SykiHDc5iF3PboPM8zAYWJLcM8DxkYCcyyvXBipCAot3Yul2R5x2BbEQ2Wi7jrWbTdav6u70QszqHvb1tXLs/8pbHrxQz8MunZ0xPY5qzoUg0z5mU3QYTLK6/r+zO8CXXXy73o9uJtz/YP9za8/W5SPoILvehSn+rNIBgPulXBp8mktK7gYQGbIEeXtsFRwgQnoXUvvqep/ZGy1AKvgkrvvLGRlYopAYkiw3YCLENY9d+Sy7gLrKpa7ZJrLp7zcyBdfyetYx3/On4DnoWyJw=='
    ),
    ('lobed', 'veins', 1): ((170, 172),
        'eNrtVrGOI0UQfe22ehw0MyNI+iRrxxI/0CcCfGCdhz8ZhAQhjmAlTrttGU4X8AEECN0nXEh2bSxBctKmG1wwK6SLCGYlAgfLmupd'
        'sdM1Mz+A5A56rKdyV9WrV9UNHNdxHdf90oOoHwLH958RR1/efyoGvn//eT50TNo53NmwP+PgRIRd7jphmbAb28kgHCjWjqG1Cntu'
        'WAK3d2FKwUzPrAwfy0wziTmQ7LhpaRIHcfFyzlwJ9waYZ7JDrK6IqjPbyWAT4viOgyr40tuGo1Xw/UwxT0hCwYQvY9TIRhAFhge1'
        'vsIZNI8femHUDDU3xYVwv0FsUgZmXmtLXPNqncLvID/tqMZpk+vHzdbxulTr9Sb5izvzKZ05+3rH44IVtyO9fMVT2KDw8OcdXm3y'
        'I7TiesP2h9qLuuzwOj/TKL7nYHn+S+XFK24qk4sNrO2klde1JQl2Qr0kq3SVtcATokgGZX2DfRv8IZSQqifqSdtA2WJGvFjWdh72'
        'HWlITuO202qkPMn9Y49pKyFfVaeh/rUWf0amKnMu1L/+oH6I1fvP3EnQppTTtNWknog9RnM69OrBWeM9HpU48bt3ya//gcmbCR4r'
        'JGP9YV08+CrWTjaQvvx9ivoBXRrSJezYVH4aEeAoUYcvnhvZMpjfEFUGo0a4Vcs+xTSj9lnARsPFZvWITkggWav84WcKomEDo9Lk'
        'v5LXTkU9JElrpcatwS7SsJ1gSjwLpyO5h4nwic6h87jWYXgsSNPbS97twI3BlARQRD1IjF0jqRcQkQb2Cl81+FKtEPXheyQL0nX1'
        'uYtb1k9N+RRyzIavlusxniL0YCwYa0vsJXUBdm2+QqVEyxOHMjtEfJd7mmKXUNnf7QHnOnMolvQjoitp3AvgdYPiKs72hVGY3OJQ'
        '5xFabF0tNoeDEWxi/KQxyShV1vHFPz6Uy4g6Rpc3wEdkWvCZs8eYZk5naCUH0D2w2fM2zJwxyJfd26Uz3NnF0VknGDCV15MB029X'
        'Azdiuhz3QbH1VR89heqDVIS+qXzbvWDv/u9h+/GnkP3/k/u8h+4T9Hkp3Aw9XuTPYZ530ZUfeCmk6cBL4e5u6lE4H3oIyOPr67j+'
        't+tf/fHTFg=='
    ),
    ('lobed', 'veins', 2): ((170, 172),
        'eNrtVrFuE0EQnfUee1dc7JNSsBJWbIQEdBxCgosU2ZYoaCj4hI3SAjKiIEIobBKUCkFLAf/AJ2xACg1FPuGitEicROPC+Ji1jTJz'
        '2R4h5Qrf3fjtzps3czMLcHFdXP/sEiFjNw9Zf4WMsgxZW8yFXT4Yuq5YPkQUOvz7QHcVbnF3HUus6eLWhnd0g5FeeNI0AiWnc1LC'
        'MpIn830LFqv4uGB3ypBLx1sVsy7e0jYzqsXNGmYdz3+zqE+NMSxcf2UEJp5lHxIK7a8fYFwSBNW1pVZO5tC1LWI1MNGehRj0KSnl'
        'RRxBvsOg49Tr2JIVzZz0UAdGWipr0XHQFUegaQ7F7gwJtB0TdqxfPcKy2mDQNswk+hKWQgVmFMug1FlC18sKQXJXgqURvPD76Tyj'
        'YpXKzANgRZyhUCAxgIzXJIp9ijpQqomvzaILjlLF2DVcgqoDjhgj6Lz3mlhFoUb8LDXsaFbaCjQmUb30PIj76ylSOKy4gp+skaDb'
        'wGgN0Ynx+aGlKfpglI+W7ZrCHOoYARQuV9J2xdvGtwp5LmzqmDEtRAwDmHDops2M3I65MU6gA8/LRnMYWpiq3htmS8R3WKnsBnMl'
        '9sCJBw8brrp5AvrKSPJNv8FI2G3grtpjpQvJBQAxg3v7CByzhnFrIsuxYn3otY1jW3i5CKteXZpEWJPSPiRcjenQKQJpWuTE/+US'
        'yBplhVnQtqE0wGoJrF9ESFEhW8U+C4ev43ajW3Sx0iRw9SWWFORFQ5JBF8pY2IYktcNa077SRiR7deWwKrDSaMd69nsGJocu686q'
        'GJZKRhg/3fg+wOXSoFRQnEmgkE99kOJqQWYJLlN1+cWHas/Uwo5k6tQYB4kkXRAVqY8ktgCb04bp0qlZb4FuVIadyWOsYtZJIZOT'
        'oRST4Yxjr52WN+r9mo8oJWe9adacWKO4/sFHmPEp6x3zr2XgGYjDqKG3L4G72YiRiir8qtVm1Gq6uglHmemfm8P6tjo/TOU+QPvc'
        'eDWh+Zw2xtty9uoANA9BpQtN8qchY9oPnSRC7qsQ0yf7AVdxGnT1eBwwxns2FFVovQqeelDn87qsBWKIxOcAtLwzb7INTyprnGbm'
        'pFwAKkNJgdXg+SwUP/RC8YsPIejVUTCDQVncxXn4f73+ADOTwSU='
    ),
    ('lobed', 'spots', 0): ((170, 172),
        'eNrtlM0JwjAYhhMK9iLt1UNoVnAAaVdxkKIdxGHqAuII3nq0NyNIY3L9fAYo8r2QQF4evr+EGKNSqVQq1X/pQWZ1FEY+dzdhtmmVbxGgyOfYCrQbjakniS5p62eB+kxthGkXKtNj8f16hz2SuSXTInogs0T0Z2D7PDA57GJIqaJEQ1o7OVufUOOEWQeo1cYBCnIB26TiHfb5JLT6EDrho6b8V3pC/k4oZmoavBKKak+Evqgrj0Fncs+Uqrzox6ZSrUtf6kssmA=='
    ),
    ('lobed', 'spots', 1): ((170, 172),
        'eNpjYBgFo2AUDBvAgU2Q8QA2URlsgsxYlcphtYsEpQVY7RqNrlEwCkbBIAAN2AR5HmArTN8Rb6o9NkH2H9hE/2MrTfn/YFNaj81Z7NiVYjOVHZt+hgqsRTTWcDEYTS+jYBSMAhgAALumDy4='
    ),
    ('lobed', 'spots', 2): ((170, 172),
        'eNpjYBgFo2AUjIJRMAqGFWDBKuqATZAVmyDzH2yi9QewKf2BTSl7AzbRGqxKsZnKYINNkPHAaNQOdfACmyAb1uTih02Q5wHRSXsU'
        'jIJRMApoCwBLjgky'
    ),
    ('elliptic', 'veins', 0): ((204, 198),
        'eNrtVr+LFDEUfpmMyRRhJ4dNYNfbEdsDcwoyyLKMIP4d8bS02PIEYTO3y10jnKV29yfcn5DzBK3UP8BiDntZu0W2MFfPl0IQBNlX5s3ky3vf934QbW1rW/vn5hLnbJX6I+kI+FjwxPdmkHA8vYvPd05eY8cTkQii1tghz5rEmy5Sb1IJiKXFVwlqcUKKjHnosCZLJPYQg3M2szCIXDUQu9GWwSDOXYAplPKIDIR4aBSUTqXcTRie36EX6Dyjx9TBPJUWK8feW9Y4T4MdCM2p3oPRLcl1mAmGoYPbTCrIhN9/h7Dzkr5BbP2KB4jd2DEWmnfPCelAsNYQ0kFxpCyU2kTZABXVaY8agmF0QCghLudvoT7a9bBB/SAT1UdCZa/IjzQSVNSAvQOpyMmvUZ7IZOwMUUHu6wiVhW7aiyvU1dyCl+0CQCyU+k4jEJ7SU4XiLowLul9hGV/tHxMgL17yUhMgL6Yjb6iE6RgS/egrszJUk+yTJCPTrqgR2555VEhul2TYQ8pUMYTQZ09YHWsSRFGSy2gGJFjxN0YCCcow9G7G+1zcog+sDEMD2q8pf5LsYw+pmnBE3iFdxUBATQYWOeqLtliseBwvs55jKkMeEPTMXHM0B5K97dcMDDdBn8vuuO5HV7DuPi8BRw8kqRyVRcx2NQ+IvBk7vUR9WXayU2AiKf1+QtMCCccGcrYP4mRMIH0BmVUxNL4CDVu7HKlc0DPSYANxSnzSUZ99BLvfPToJqJvyVqzRrAgqn4ORPoiNaHwFUm4EnazQ9LRKbKgAVzm7S6i4Yw2trvsUeO1Rk1egx0tuvPGA1lw0dLCLBveYtaeoC9qal2s4dlz5Cw1Puiw3QAU0YKcbQkNSZZO4BqA33cALEdWj1NZqUzuoJzw+lzTfwN3Ajtd4f+sSEKmtlcapzTgc4vOMEmHoP1yxKUv9UKQcTWrv/2s3bW1rW/vf7Dd7EKED'
    ),
    ('elliptic', 'veins', 1): ((204, 198),
        'eNrtV79v00AUfuczZ1O5dljgWqWJEUNXl0pRECbxxMQfcVElJgaPmcqFoJSBoo78GYyM51KJpRJrkTpcVAYmZIkliArh3d8NDCCG'
        'vPG+5P267333TLS2ta3t/zT2ywEI4wC4y1XkAjLHuS5wDI85Ykh/hIFCvnLkqlIIhEwrCChBGgLXkkOAG7WNG8j0E1yFIBw7kwzH'
        'VqmPy6s07m3iRdjT03AD0yBKpaPn+hoD970O/D07x56UrHHZpppDinDyIkIMERRmHmQgX65g8OzWuYXBFd+bw36YTQ35HNAA395h'
        'VjOLqjie2wQBlCcG3175UOPbs0bAIthMS1gEFzTMQU5hT/rZEHS2eDbtKFDfBt+x1QzO9tjzUKcUTWWIhs8wu0I8D+j4wxTxfMCv'
        'pAWdYi+DaKIBQXxJ+yIwMNtLuY95ME1fQGVJSoEJkhsoRjdOFF0gsdudaeRpQEeCJOD5imJJFnTKUFcFy3a2jT490g+8NhMCRb3Q'
        '+O0QSUj5gIB85YrKmgCnfhJVGiTr5cQjQvWVFJVQKb7Q9yICl8Rq9vntbdhydmpKCIiI4UuSFILjr41oU9ZGYssqzUHdJfHT5rhF'
        'wuZ2tj41FDRtMtPVSoC3MiHGmyLaIeJUc06gtTsLirqotXlGnQuknJeaHqdV2xPvEXvP3wDNHvlBzUBr09Gwa+Akjc1dvYlUqt+8'
        'nwfoMvrzRnfgY3VGEkpqYGm5aDeqQ9tGAOkcFcWE9sDAJJz5HMl5HPoyRHKeKKlMgHLVkwUNEUCLjBn4j5s6hmXrnEpYtrZ4/7kz'
        'RyPZMPzjaxg6u8dPYvSCLnVgVQIG44z4EU3RTJIYBhpNmL9lhnAt6n/jKCnWxM7xsHJYRQNEMV5abGbxblIf4MWSfrzDFKTnc+iq'
        'b/JD6Cqod/Hyylcrx7o71n+6OHdcgHJt864QwuVJuoDUBei//l1Ahau89ffa2tb2j+w3CM2xQg=='
    ),
    ('elliptic', 'veins', 2): ((204, 198),
        'eNrtV71qVEEUPpOzzF1wuDfliDfZVV/grha54pIEBJ9jJG2QsXKFSE5YMCkCpkwR8BUsrXSSwspHsLj2Ei7YbBFcp3a+sRDtdmCb'
        'OXt+7vm+8zNEq7M6q/NXZz1z3+xmBJeC71lnFIwdY8FOztQyY+qesfBeLXbOsIZbOKwxx/8fkMECS00mTxSwIDC+V5Jxod1OJk90'
        'gy1drOGoTDOkDgc1Vl9wUMJQg9eogJbKIWEw9sc4I2zlJYSIHtBPFFKgmTpFhog7SARNG+LGELynLBg8iz/CkcMJFPUGs7/RmCCF'
        '3BZYZEbtU4ec2KqD9HRNQeorws5ZQuixCg6hpwaFEoSe7reKJWJOpU5HNeKB1bWjFgg8PRKFeHBF21QiuM9pFrXAVwTq7gqEW8kp'
        'pD9pdriIbUGICT05WxhUkkrCNohqcqm1egcszU9sQ1MQUhH2hBwIyagLFJOjuuioBiVM7aaSFCQ+od4b0HS0199kHYBUyeQzCQBp'
        'yvNzjXqwjzFZxPPQFfIigKCOItjfq9RHJJNV/cP3aV+Jn84xW4mgjnBD6jSkY1k0qIhnZQNIqELR9aklHvKZOpaUhKUfBT2L7n8X'
        'jOQ6/gBILRs6IAC3L+sYEAAp1NOSGguKe721FALoguQDmrmxSSxJxwmQZrY8oFsgUVPyvmnTz1OLyP4Q0rooPTNv0iTRGLvSRNZe'
        'p1FF2oxI9ajLhxs1F1D2XFkG/L8jxjemS/eYPdmSMEpZwAUtKDaXJOWmir0l5UccOs83EKrc8+Z9Av0xkvm1oE5bEn9ErqNxM2PU'
        'iVpybrCNSu+ZkttgdqsfWg8PwIDRC2ubLkWVJsG5a1RIKqijHhUSyyCyCo5i61GPirl4IrQLrkvVoglaDstCNGi0xtVTqoCHEbUB'
        'Th5LjwlOnjaWZI23gH4XTntPl3jaO2YPF4fOFHjz6hpfwcUrHIuHgqsZVLDqrcyQoOUPBVxyPGMFajVWIG+xAs32Msvuq089Fhwu'
        'MxqHuQdJl7nnnILJCZqcIPwzF+OcIPOyobWcwjAncJR7R2QEuXdYZl//k4vV83h1/uP5BcPnws4='
    ),
    ('elliptic', 'spots', 0): ((204, 198),
        'eNpjYBgFo2AUjIJRMApGwSgY9uABDnHmAzgk+C1wSNjjMIrxPy6TfuCQMD6GQ+JdBQ6Jybi8Yd+Aw1F/sIvL83/ALlEhPwObsAFjT00CNi8cYDB8gs3eZwxsh7E5lv0GgwQ/NsfKA7EdNpP+AQlsjmUHeo0Rq0k/SIw5BhuSU03DaI4aBaNgFIyCUTAKRgF9AAAkiRxI'
    ),
    ('elliptic', 'spots', 1): ((204, 198),
        'eNrtlD0OQEAQRrGFDq3GGZSO4xSiwgEcyjGUKrWoSdDPK4go5HvJNvMy2flJxvOEEEL8iZ5EAvGAEjISe2fHw1XjF1/gk4hI5CS696oqqVr6IxxAtJDhNkhwC4mJxCd7ogbj20enpiHO1GBhBNOrKGsk1VWU9cV4vsY6m+e2XX1n20IIIYQQDzkAc3wRKw=='
    ),
    ('elliptic', 'spots', 2): ((204, 198),
        'eNrtlLEJhUAQRO80MPsaKgg2YfAD8azEOgwELcNyzGzDzNTQ4AduATPpB3EeXLLDMsfs3jknhBBCiPcQMaFciDDsuO4PIiRhxULxIxbpSYSJ3XZgwv78EeVMsJQ8ija2YgXjs44RNdjoPEoqDXaQRX6ZxYyGbcUeebd2vmht2BL48y/pXsyeLK2rOyJs7Ik1zIJ5f9hlM31YQgghhLgBZfkaZw=='
    ),
}
