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
"""


REFERENCE = {
    ('lobed', 'veins', 0): ((170, 172),
        'eNrtVrFu1EAQnbm11g5ZnY1oNsLKmQZKlgaliBIXlPkIRyloImGoLhV7XESaFCn5DOgo93RSqog6pSWokRHNRQo6xifF9tpbQEGBdHPSyXp6O56defNkgHWs478M4UTNH1MzF3XgpCZ/QZ07QHYbOdD9mXbVKl1p3dTA2QFXscJZrEn7mBbccTw1WR+9EgMH1eikj74QrA+Gy2nZR0+DB31Qplr1QDwNsE+NUm11e3Ud5nWoGVA+1aXyIWXl2zY1PaGOqsOFRRVYCqJKm2o4JYZHWtrqM1UNK2pDL2RVAVZUXtN9Rghdgf7iZuQ7CeUQCBLCxb06waVHYjejGw1fdVHfwIwDoi4X9L7dmjpmPyZaR9UIzmpwQ7Nyp+oK0szuwEMOnGHVFQnjOqlSMM5kddz49fnnaMQ3rMbCsTy4G4kZ4tRIRnNVz8503azPMsblEpDxoJ6j2ZqDoaKEkmZaN4sNM46Q4BSuZU1N813IowF8THx830wLTYg6GQ4gV7U8U6qArlpkWdjaewEqQnjMBH7Auq+o6fn+G5BGmWa4isjoF3DNvUazDHQGEQefet4IkXrCVlKSMGgpQ+/mpDqcBtAsTSrZ94oqTnRrv1Af6Uqgx2XbuBR5QJQdsMu2cfkzPWP+0ijFGi/AL4pHagwMIW+dP4Ln3KO3Ba3znGVospRSWl4SQzz0aGw8by/WRGdFCnv0a4WS/KFHYsC2wdCsfsr09Rys9czUViFGi8SykiHDc5iF3PboPM8zAYWJLcM8DxkYCcyyvXBipCAot3Yul2R5x2BbEQ2Wi7jrWbTdav6u70QszqHvb1tXLs/8pbHrxQz8MunZ0xPY5qzoUg0z5mU3QYTLK6/r+zO8CXXXy73o9uJtz/YP9za8/W5SPoILvehSn+rNIBgPulXBp8mktK7gYQGbIEeXtsFRwgQnoXUvvqep/ZGy1AKvgkrvvLGRlYopAYkiw3YCLENY9d+Sy7gLrKpa7ZJrLp7zcyBdfyetYx3/On4DnoWyJw=='
    ),
    ('lobed', 'veins', 1): ((170, 172),
        'eNrtVrGOGzcQfRQFrgpmd5E0DCDcCsgHhK4ix4K1+ZM1AiRlVCUHxLijoMRwkQ9IEQT+BJfpTEWAKwPXXpFiDwZcpdgDUqg4SBn6'
        'EC9nd38ggFiQi4fZmeHjmyGB0ziN07gfehD1Q+D4fhlx9MX9UjHw4/vl2ZCbtOPc2TA/5eBEhFnuOmmZMBvb2UFwKNaOobUKc27Y'
        'Bg7v05SCmV5YGRbLTDOJOZDsuGlpEgdx9WLOQgn3BphnskOsroiqC9vZwSbk8SMHVYildw1HqxD7qWKRkIQDE5xBI5uAGJ7U+gYX'
        '0Dx/6IVRM9TcFFfC/Qmx4VLIvNaWuOaxzuF3kI86qvFjk+sHzdbxc6nW603yNw/mFfmcfbfjecGKw0gvX/ItbFB4+MsOrzb5BVpx'
        'vWH7c+1FXXZ4nV9oFD9xsLz8vfLiJTeVydUG1na2lde1JQl2Ur0mq3SVtcBDH4qCEvoe+zb5YzhCOj1RT9oCyhYz4sWysvOw70hD'
        'chqXnVYj5UnuX3hMWwn5qjqnP2WtxVvXmqrMuXD+9Sd1a+q/cmdBm1JO01aTeiL2GC3I6c2HYI33+LTEmd+9S/74D0zeTPBAIRnr'
        'z+rig9di7WQD6cvXU7SxloZ0CTs2lZ9GBDjaqMPXz4xsGczvICnTUSPcqmWfcppR+Sxgo+Zis3pEHhJIViqv/UxBNKxhVJpsKnnr'
        'VFRDEj4tNQ4Gu0jDdoIp8SycTiNTKpMvdQ6dx2cdmseCNL295tUO3BlMSQBFVIPE2C2SegERaWCv8G2Db9QKUR1+RLIgXVdPXFyy'
        'fmrKx5Bj1ny1XI/xGKEGY8FYW2IvqQoQ9QyhUqLloUP5+THiu9xTF7uGyv5pHVzqzKFY0kdEV9K458CrBsVNvNvnRmFywLHO496w'
        'dbXYHA9GsI7xq8Yko62yii/ufDguI+oYXd4Bj8i04D1nPxtTz+k0reQIugc2e16GmTMG+bJ7u3SaO7s4OuMMA6bydjJg+sNq4EZM'
        'l+M+KLa+6qPnUH2QDqFvKv/qXrDv//ew/fxTyP7/FD7vofsEfV4KN0OPF/lbuJK76MoPvBTSdOClIDx11h6F86GHgDy9vk7jfzv+'
        'BWoe0zw='
    ),
    ('lobed', 'veins', 2): ((170, 172),
        'eNrtVsGKG0cQrVINPTq0JUEOaWJhDeQSfMmEgBnDYsn46o/oYDA5hDAhEExINm0vKJfgXHOw/yGf0OvAxkd/Qpv9gAz4osNak2qt'
        'jLpm+x4C24eRpnjdVfVeVdcAXK/r9Z8tzBmP6pz1Xc5INmcdCRdu/yeFUpPbt/zwx6f79y9+6hKrvvyZwPP0gL0La9IMRrTbOEIn'
        'nIXds5G5vriM7lwYy8uNjzph3b0VeiKMavd0TtLSxoeZFfJUmO3I+SsNFTcxyhrGVWKt7q4NBwX4LIWqG28ZWsGtB4KAjYlR4J0q'
        'DUpFEldQHwtoqyOPI+xS5SiS78FSwtbKNFMPczwDk2qIT7ccwMQLYlvzU81ldSSgE9gS+0KXQpEV5TIIBsZpWBQYRE+ZxYPxE/gh'
        'nseyJtCRVxacltXGpLIn8iAVcMwpnO/l+bDGkf5mLqptpxRMoZsKcwHT3zGQc+IEi/+EBo6NcKbAbMipH2Mch1U/1hzCaScZfOks'
        'gZmAYHDBTmzUJy1NrMCqKJc4VcMOOsiWk1Xk5vjboFehrtFpma1uqIR7sJFQ62aWnpQwKFjm5fvQDnrWwYVarCWx+BpudO5IuMIT'
        '5/DXhwNX83oM5uaKZG/+DSt0X4PszUmrTDOSBABu4eMTFr0VF8ZyQ7ZVojJ+cWXpmkhXEtWiD3aMzmoo0v09Q4xmYBoVceB46sex'
        'bRNddyoYN2Aa7r8LIO6LgkMsaStKcAKeX9uJpLSdcxMQSPYJuSrqhv2lpN6bQyjRkegg7D3XmgGDbpWo13eeqwKdSW+s795vwdbc'
        '2mkFqWbZKSrAVynXfM0sg7VaQXOgQHFH9msN1mIyS3jbug+vYqruwFYF2vbaWg9jSotqDf0ZcQKuTi5M4/WFvTsCQ4NptaU3XMWV'
        '6HjWZkkYFlsJ/fQ8fP4e+3AQiz0o2i4uxLB6FQu+TGBx3bZRssWblbDG+9PhqbzI8TiWwJ3ZqhLd0nFXq6+K0XDIfQZnM1tdmcPm'
        'C0Xhyng9iUUyXDY3n/VgvO1nr8lA6xyUfG4if5sz6ir3JZFz3+Ui/fkk46rUWVfftBlj+czlssrtL7NfPQHgKi+3MjkU+GcGGr4E'
        'MZ0uO0HNAIorQfkMlHKiwEfZ77MuZ13k8qc/sgdkZdVZWvz19/D/df0LPpbGKw=='
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
        'eNrtVzFv00AUfuezzi5y47DABQXXiKHrlUpREKb1xO+4CAkWBo+Z2kuDmoWijv0ZjIyXFjFVYi1Sh4vKwICQJZYgKoSZ/d2AhBBD'
        '3ujPvnffd99790y0ilWs4v8M9tMDCOsBuG+pxAcohZ+bEucIWIQ/kOEeBsrehWevGueOmdEQ0IIZCFxLDgFudYYFZOYcsxCEcyvp'
        'ya0V1pbbA0wv5Rle6VncwTZI8j6Wtm+uMfAg6EJ27IvEJGSNadv5lBQ8vCAh5BBBsQqgA/liCZOrm+cOJtd8awr1sOsGah7RAJ/e'
        'nqqZQyyOpi5FABWpxadXPTL49JwVkASbGAlJcEHDAuwpzmSohkDZ8sW4qwG/G/yum0+QsrQbBEgpTWMZ5+i4mVsin0fm6Gwcgg8G'
        '/Eo6oBR7GSWjCTBIKGlbRBbu9lJuYx+M8wPYWdJKYIMUbgcB68cjg5qR2ZzM0EoDNhOJBD5fikySA0pZ6uto0d5t058em4dB2wmR'
        'piy2YTtFGlMxoDvAmpqqmoCnfhDNDdhsUBBPCBVlRUkFO8Un+lYmwAesZh9PbkHJ2amtICAShu8FSTF4/zOzmoZtpOPY3HDAuyJ+'
        '2jxum9BQ74OxbUGaC+xqGYK7MiXGGxLtFJ3ccE5A2v4hJX0C1im61L1AnfPS0JN83l6JZ8Te8tegZxdhVDMgbb6j+hZW0q69Z9ZQ'
        'l9poNHmKgGz62yKopZ6TrCBQ0+J9W6guSStA69wpyxFtgYJJOQsZauedOJQxauepltqiISQ1o0MaIoAOFbPwizUD79zIFIRpG4dG'
        'jYBuT1FJNg4/ewVTq/v8uINu0AVxp1NQGO+Iz2iMapLEMELFasOeHcLRZOMrR5tiJnIF7qgcsmiAxDO0OOXwbFI/xyMZfX8TEzTt'
        '/hQutWELPHJG9SYeXvly6RmD982fDs5dH6B907wvhfCtJH1A7gPM3/sv8AGlj97qf20Vq/hH8QuhQrSA'
    ),
    ('elliptic', 'veins', 2): ((204, 198),
        'eNrtV7FuHDcQfdQI3AO82VNJAWvvOf6BFVJ4Ax8kAQH8HbTVuKQrX4BDPAcBkgsjcenCgH/BZaqEcpEqn5Bi0wfCAmmuMCyzNh8L'
        'G0l3BK7ZueEM5715HAK7tVu79VXroPC9Py0YrpR/F1twqN2CG05KW90UtnpcO/rdbE9ecQ+/9dzjnP9/HzU3OPSFOiFyQxT+3Wgh'
        'hPUne7xO+DCjO73ZQ6AV72cYeVIL8ydPSoV6yB4qulMzK4DxZDHQiojTZxQifIuPLKWIFU1WIGPdsgLitoYFBe+hqFLwXMt5o54X'
        '8MJccvb3dqCGSg+VNlldrTGyIK4bKT19X8H8xbDzDgw9MdEz9IytNgqCnp3uX94w5szNz13LeOBs68EOHvC9GsaD9zhGw+B+jRVl'
        's0SMd5XCbfQlpT+seN7EroKQvSZ4V9WsJY3GY5LV0ZW15i3Z6fyF67EkKVXxTJFnNaAxb1hOHm01grAzYrhjNAdJXmAKNREdG+zf'
        'ekBAmuvRH1AC0lLOX1umwSHl5JgQxrHSp5EktUlg/zPPYyQyOTN99y7XlXR0SdXKlLlNcDPqDD1saos8K++xavqchGYTq3E6zXaS'
        'Rl6ZS81J2Gw7tasU/nNDp9fpR66MQWqsQeAOTZsSIiCN7bJB70hzHwwOMRIVRIjszk0icQPbz0hlmzVukUItEUI/5Mcz28T+GPPj'
        'NUFEWhxlHgvf1Im11+R8ru9gJqby8YM5V9L2MndC+N9pHfp6zOeYM72vsctpIBW2SOKScbbukrYQfrzET98oaT2Z5M49EH2sMFsr'
        'U9oG8hsLnTZvB2FKNCTa7h+z1nu00UNyHZp/rZ2tD/Jrz26d60fkMY6i99dMg83VZjOxOUd0P7GKXsUuMI1KtfhBwUjbmMFcEI2a'
        'NZVaIrS1b5eYkwgd0pgxUJF/AHrzDKklaz7CTaf0tg+4uuDjgUig089YV3zyGvswp4NXvFQ6w5n3K+rgzC+6YoaV/FrReToId8Bg'
        'uQOC4w5YnRWG3R9/n7jh+c1YMJQeJIX/Q0oOdcnQlwzxPwuxKBkKLxvslRxmJYNH6R1RMJTeYXBfHGL3PN6t/3F9AjPIycM='
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
