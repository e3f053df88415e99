#!/usr/bin/env python3
"""Writes the seeds of fuzz_image_fill (tests/fuzz/corpus/image_fill/): a
header of 14 bytes laid out as fuzz_image_fill.c's choose() reads it, then
the image's rows (with the chosen padding) and the mask's, so that each seed
is a fill that runs: a grey image with a mask, 16-bit RGBA with its alpha as
the hole and an odd stride, RGB exhaustive in a search radius, grey + alpha
with a 16-bit mask, a fill the callback cancels, and a refusal.
  tests/fuzz/image_fill_seeds.py   (from the repository's root)"""
import os, struct
d='tests/fuzz/corpus/image_fill'
def header(w,h,ch,depth_sel,pad,no_mask,narrow,mask_ch,mask16,win,even,minw,tau,interp,exh,sr,seed,mhf,idiff,cancel):
    b=[0]*14
    b[0]=w-1; b[1]=h-1; b[2]=ch; b[3]=depth_sel|(4 if mask16 else 0)
    b[4]=(pad&7)|((mask_ch-1)<<3)|(0x40 if narrow else 0)|(0x80 if no_mask else 0)
    b[5]=((win-3)//2)|(0x80 if even else 0); b[6]=(minw-3)//2; assert w<=32 and h<=32 and win<=13; b[7]=tau
    b[8]=interp|(exh<<1)|((4|(sr<<3)) if sr else 0); b[9]=seed&255; b[10]=seed>>8
    b[11]=mhf; b[12]=idiff; b[13]=cancel
    return bytes(b)
def image(w,h,ch,depth,pad,hole,alpha_hole):
    out=bytearray()
    for y in range(h):
        for x in range(w):
            for c in range(ch):
                v=(60 if (x//3+y//3)%2 else 190)+7*c+(x%3)
                if ch in (2,4) and c==ch-1: v=0 if (alpha_hole and hole(x,y)) else 255
                elif hole(x,y): v=0
                out+=struct.pack('<H',v*257) if depth==16 else bytes([v])
        out+=bytes(pad)
    return bytes(out)
def mask(w,h,ch,depth,hole):
    out=bytearray()
    for y in range(h):
        for x in range(w):
            for c in range(ch):
                alpha=ch in (2,4) and c==ch-1
                v=255 if (alpha or hole(x,y)) else 0
                out+=struct.pack('<H',v*257) if depth==16 else bytes([v])
    return bytes(out)
sq=lambda x0,y0,s: (lambda x,y: x0<=x<x0+s and y0<=y<y0+s)
base=dict(pad=0,no_mask=0,narrow=0,mask_ch=1,mask16=0,even=0,tau=0,interp=1,exh=0,sr=0,seed=1,mhf=10,idiff=0,cancel=0)
def S(**k): x=dict(base); x.update(k); return x
seeds={
 'grey8_mask': (S(w=32,h=32,ch=1,depth_sel=0,win=9,minw=5), sq(12,12,6)),
 'rgba16_alpha_padded': (S(w=24,h=20,ch=4,depth_sel=1,pad=3,no_mask=1,win=7,minw=3,seed=7), sq(10,8,4)),
 'rgb8_exhaustive_radius': (S(w=24,h=24,ch=3,depth_sel=0,pad=5,mask_ch=3,win=11,minw=5,tau=40,interp=0,exh=1,sr=9,seed=3,mhf=20,idiff=140), sq(9,10,5)),
 'greyalpha_mask16': (S(w=16,h=16,ch=2,depth_sel=0,pad=1,mask_ch=2,mask16=1,win=5,minw=3,seed=2), sq(6,6,3)),
 'cancel_after_3': (S(w=32,h=32,ch=1,depth_sel=0,win=9,minw=5,interp=0,cancel=3), sq(12,12,9)),
 'bad_channels_mask_size': (S(w=20,h=10,ch=5,depth_sel=0,narrow=1,win=4,even=1,minw=3,tau=255,idiff=255), sq(5,5,2)),
}
depths=[8,16,8,12]
for name,(h,hole) in seeds.items():
    depth=depths[h['depth_sel']]
    ch=h['ch']
    if ch in (0,5) or depth==12:
        body=bytes(range(256))*2
    else:
        body=image(h['w'],h['h'],ch,depth,h['pad'],hole,h['no_mask'])
        if not h['no_mask']:
            body+=mask(h['w']-(1 if h['narrow'] else 0),h['h'],h['mask_ch'],16 if h['mask16'] else 8,hole)
    data=header(**h)+body
    assert len(data)<=4096, (name,len(data))
    open(os.path.join(d,name),'wb').write(data)
    print(name,len(data))
