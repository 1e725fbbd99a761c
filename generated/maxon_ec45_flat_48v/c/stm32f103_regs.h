/* Generated from template templates/c/stm32f103_regs.h.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 4e4bc402b3ee91505838c88f91659557d0005f5a8b56d60c19ecc3e2f665b3c6). Do not edit: regenerate with `bldc-codegen generate spec/example_maxon_ec45_flat_48v.yaml`. */
#ifndef STM32F103_REGS_H
#define STM32F103_REGS_H

/*
 * Minimal CMSIS-compatible register header for the STM32F103 BLDC port: only the
 * peripherals, registers and fields the port uses, with the names of STM32Cube's
 * stm32f103xb.h.
 *
 * Every address, offset, bit position and IRQ number below is read from the vendor
 * SVD STM32F103xx v1.3
 *   codegen/data/STM32F103xx.svd (ST STM32F103xx.svd v1.3 (Apache-2.0), as shipped in pyocd's svd_data.zip)
 *   sha256 1d92b65aaf397a18a599fb6a840812015ad379cdcc0cc3687f673f63e7445367
 * by codegen/svd.py; none is typed by hand but the core peripherals the SVD does not
 * describe (the SysTick timer, the DWT's cycle counter and CoreDebug's DEMCR: see below).
 *
 * In an STM32Cube project define USE_CMSIS_DEVICE_HEADER (and STM32F103xB or the
 * matching device macro): this file then includes Cube's own "stm32f1xx.h" instead,
 * and the port compiles unchanged against it.
 */

#if defined(USE_CMSIS_DEVICE_HEADER)

#include "stm32f1xx.h"

#else /* !USE_CMSIS_DEVICE_HEADER */

#include <stdint.h>

/* CMSIS access qualifiers (core_cm3.h) */
#ifndef __I
#define __I volatile const /* read-only register */
#endif
#ifndef __O
#define __O volatile /* write-only register */
#endif
#ifndef __IO
#define __IO volatile /* read-write register */
#endif

/* Interrupt numbers (position in the vector table after the 16 core exceptions) */
typedef enum {
    EXTI0_IRQn = 6, /* EXTI Line0 interrupt (SVD EXTI0) */
    ADC1_2_IRQn = 18, /* ADC1 global interrupt (SVD ADC) */
    EXTI9_5_IRQn = 23, /* EXTI Line[9:5] interrupts (SVD EXTI9_5) */
    TIM1_BRK_IRQn = 24, /* TIM1 Break interrupt and TIM9 global interrupt (SVD TIM1_BRK_TIM9) */
    TIM1_UP_IRQn = 25, /* TIM1 Update interrupt and TIM10 global interrupt (SVD TIM1_UP_TIM10) */
    TIM1_TRG_COM_IRQn = 26, /* TIM1 Trigger and Commutation interrupts and TIM11 global interrupt (SVD TIM1_TRG_COM_TIM11) */
    TIM1_CC_IRQn = 27, /* TIM1 Capture Compare interrupt (SVD TIM1_CC) */
    TIM3_IRQn = 29 /* TIM3 global interrupt (SVD TIM3) */
} IRQn_Type;

/* Peripheral register maps; RESERVEDn fill the gaps between SVD address offsets */
typedef struct {
    __IO uint32_t CR1; /* control register 1, offset 0x00 */
    __IO uint32_t CR2; /* control register 2, offset 0x04 */
    __IO uint32_t SMCR; /* slave mode control register, offset 0x08 */
    __IO uint32_t DIER; /* DMA/Interrupt enable register, offset 0x0c */
    __IO uint32_t SR; /* status register, offset 0x10 */
    __O uint32_t EGR; /* event generation register, offset 0x14 */
    __IO uint32_t CCMR1; /* capture/compare mode register (output mode), offset 0x18 */
    __IO uint32_t CCMR2; /* capture/compare mode register (output mode), offset 0x1c */
    __IO uint32_t CCER; /* capture/compare enable register, offset 0x20 */
    __IO uint32_t CNT; /* counter, offset 0x24 */
    __IO uint32_t PSC; /* prescaler, offset 0x28 */
    __IO uint32_t ARR; /* auto-reload register, offset 0x2c */
    __IO uint32_t RCR; /* repetition counter register, offset 0x30 */
    __IO uint32_t CCR1; /* capture/compare register 1, offset 0x34 */
    __IO uint32_t CCR2; /* capture/compare register 2, offset 0x38 */
    __IO uint32_t CCR3; /* capture/compare register 3, offset 0x3c */
    __IO uint32_t CCR4; /* capture/compare register 4, offset 0x40 */
    __IO uint32_t BDTR; /* break and dead-time register, offset 0x44 */
    __IO uint32_t DCR; /* DMA control register, offset 0x48 */
    __IO uint32_t DMAR; /* DMA address for full transfer, offset 0x4c */
} TIM_TypeDef;

typedef struct {
    __IO uint32_t CR; /* Clock control register, offset 0x00 */
    __IO uint32_t CFGR; /* Clock configuration register (RCC_CFGR), offset 0x04 */
    __IO uint32_t CIR; /* Clock interrupt register (RCC_CIR), offset 0x08 */
    __IO uint32_t APB2RSTR; /* APB2 peripheral reset register (RCC_APB2RSTR), offset 0x0c */
    __IO uint32_t APB1RSTR; /* APB1 peripheral reset register (RCC_APB1RSTR), offset 0x10 */
    __IO uint32_t AHBENR; /* AHB Peripheral Clock enable register (RCC_AHBENR), offset 0x14 */
    __IO uint32_t APB2ENR; /* APB2 peripheral clock enable register (RCC_APB2ENR), offset 0x18 */
    __IO uint32_t APB1ENR; /* APB1 peripheral clock enable register (RCC_APB1ENR), offset 0x1c */
    __IO uint32_t BDCR; /* Backup domain control register (RCC_BDCR), offset 0x20 */
    __IO uint32_t CSR; /* Control/status register (RCC_CSR), offset 0x24 */
} RCC_TypeDef;

typedef struct {
    __IO uint32_t CRL; /* Port configuration register low (GPIOn_CRL), offset 0x00 */
    __IO uint32_t CRH; /* Port configuration register high (GPIOn_CRL), offset 0x04 */
    __I uint32_t IDR; /* Port input data register (GPIOn_IDR), offset 0x08 */
    __IO uint32_t ODR; /* Port output data register (GPIOn_ODR), offset 0x0c */
    __O uint32_t BSRR; /* Port bit set/reset register (GPIOn_BSRR), offset 0x10 */
    __O uint32_t BRR; /* Port bit reset register (GPIOn_BRR), offset 0x14 */
    __IO uint32_t LCKR; /* Port configuration lock register, offset 0x18 */
} GPIO_TypeDef;

typedef struct {
    __IO uint32_t SR; /* status register, offset 0x00 */
    __IO uint32_t CR1; /* control register 1, offset 0x04 */
    __IO uint32_t CR2; /* control register 2, offset 0x08 */
    __IO uint32_t SMPR1; /* sample time register 1, offset 0x0c */
    __IO uint32_t SMPR2; /* sample time register 2, offset 0x10 */
    __IO uint32_t JOFR1; /* injected channel data offset register x, offset 0x14 */
    __IO uint32_t JOFR2; /* injected channel data offset register x, offset 0x18 */
    __IO uint32_t JOFR3; /* injected channel data offset register x, offset 0x1c */
    __IO uint32_t JOFR4; /* injected channel data offset register x, offset 0x20 */
    __IO uint32_t HTR; /* watchdog higher threshold register, offset 0x24 */
    __IO uint32_t LTR; /* watchdog lower threshold register, offset 0x28 */
    __IO uint32_t SQR1; /* regular sequence register 1, offset 0x2c */
    __IO uint32_t SQR2; /* regular sequence register 2, offset 0x30 */
    __IO uint32_t SQR3; /* regular sequence register 3, offset 0x34 */
    __IO uint32_t JSQR; /* injected sequence register, offset 0x38 */
    __I uint32_t JDR1; /* injected data register x, offset 0x3c */
    __I uint32_t JDR2; /* injected data register x, offset 0x40 */
    __I uint32_t JDR3; /* injected data register x, offset 0x44 */
    __I uint32_t JDR4; /* injected data register x, offset 0x48 */
    __I uint32_t DR; /* regular data register, offset 0x4c */
} ADC_TypeDef;

typedef struct {
    __IO uint32_t ACR; /* Flash access control register, offset 0x00 */
    __O uint32_t KEYR; /* Flash key register, offset 0x04 */
    __O uint32_t OPTKEYR; /* Flash option key register, offset 0x08 */
    __IO uint32_t SR; /* Status register, offset 0x0c */
    __IO uint32_t CR; /* Control register, offset 0x10 */
    __O uint32_t AR; /* Flash address register, offset 0x14 */
    uint32_t RESERVED0; /* Reserved, 0x18-0x1b */
    __I uint32_t OBR; /* Option byte register, offset 0x1c */
    __I uint32_t WRPR; /* Write protection register, offset 0x20 */
} FLASH_TypeDef;

typedef struct {
    __O uint32_t KR; /* Key register (IWDG_KR), offset 0x00 */
    __IO uint32_t PR; /* Prescaler register (IWDG_PR), offset 0x04 */
    __IO uint32_t RLR; /* Reload register (IWDG_RLR), offset 0x08 */
    __I uint32_t SR; /* Status register (IWDG_SR), offset 0x0c */
} IWDG_TypeDef;

typedef struct {
    __IO uint32_t EVCR; /* Event Control Register (AFIO_EVCR), offset 0x00 */
    __IO uint32_t MAPR; /* AF remap and debug I/O configuration register (AFIO_MAPR), offset 0x04 */
    __IO uint32_t EXTICR[4]; /* EXTICR1..EXTICR4, offset 0x08 */
    uint32_t RESERVED0; /* Reserved, 0x18-0x1b */
    __IO uint32_t MAPR2; /* AF remap and debug I/O configuration register, offset 0x1c */
} AFIO_TypeDef;

typedef struct {
    __IO uint32_t IMR; /* Interrupt mask register (EXTI_IMR), offset 0x00 */
    __IO uint32_t EMR; /* Event mask register (EXTI_EMR), offset 0x04 */
    __IO uint32_t RTSR; /* Rising Trigger selection register (EXTI_RTSR), offset 0x08 */
    __IO uint32_t FTSR; /* Falling Trigger selection register (EXTI_FTSR), offset 0x0c */
    __IO uint32_t SWIER; /* Software interrupt event register (EXTI_SWIER), offset 0x10 */
    __IO uint32_t PR; /* Pending register (EXTI_PR), offset 0x14 */
} EXTI_TypeDef;

/* Peripheral instances */
#define TIM1_BASE 0x40012C00UL /* SVD TIM1 */
#define TIM3_BASE 0x40000400UL /* SVD TIM3, registers of TIM2 */
#define RCC_BASE 0x40021000UL /* SVD RCC */
#define GPIOA_BASE 0x40010800UL /* SVD GPIOA */
#define GPIOB_BASE 0x40010C00UL /* SVD GPIOB, registers of GPIOA */
#define ADC1_BASE 0x40012400UL /* SVD ADC1 */
#define ADC2_BASE 0x40012800UL /* SVD ADC2 */
#define FLASH_BASE 0x40022000UL /* SVD FLASH */
#define IWDG_BASE 0x40003000UL /* SVD IWDG */
#define AFIO_BASE 0x40010000UL /* SVD AFIO */
#define EXTI_BASE 0x40010400UL /* SVD EXTI */

#define TIM1 ((TIM_TypeDef *)TIM1_BASE)
#define TIM3 ((TIM_TypeDef *)TIM3_BASE)
#define RCC ((RCC_TypeDef *)RCC_BASE)
#define GPIOA ((GPIO_TypeDef *)GPIOA_BASE)
#define GPIOB ((GPIO_TypeDef *)GPIOB_BASE)
#define ADC1 ((ADC_TypeDef *)ADC1_BASE)
#define ADC2 ((ADC_TypeDef *)ADC2_BASE)
#define FLASH ((FLASH_TypeDef *)FLASH_BASE)
#define IWDG ((IWDG_TypeDef *)IWDG_BASE)
#define AFIO ((AFIO_TypeDef *)AFIO_BASE)
#define EXTI ((EXTI_TypeDef *)EXTI_BASE)

/* Bit fields of the registers the port uses: <GROUP>_<REGISTER>_<FIELD>_Pos / _Msk */

/* TIM_CR1 */
#define TIM_CR1_CEN_Pos (0U)
#define TIM_CR1_CEN_Msk (0x1U << TIM_CR1_CEN_Pos) /* 0x00000001 */
#define TIM_CR1_CEN TIM_CR1_CEN_Msk /* Counter enable */
#define TIM_CR1_UDIS_Pos (1U)
#define TIM_CR1_UDIS_Msk (0x1U << TIM_CR1_UDIS_Pos) /* 0x00000002 */
#define TIM_CR1_UDIS TIM_CR1_UDIS_Msk /* Update disable */
#define TIM_CR1_URS_Pos (2U)
#define TIM_CR1_URS_Msk (0x1U << TIM_CR1_URS_Pos) /* 0x00000004 */
#define TIM_CR1_URS TIM_CR1_URS_Msk /* Update request source */
#define TIM_CR1_OPM_Pos (3U)
#define TIM_CR1_OPM_Msk (0x1U << TIM_CR1_OPM_Pos) /* 0x00000008 */
#define TIM_CR1_OPM TIM_CR1_OPM_Msk /* One-pulse mode */
#define TIM_CR1_DIR_Pos (4U)
#define TIM_CR1_DIR_Msk (0x1U << TIM_CR1_DIR_Pos) /* 0x00000010 */
#define TIM_CR1_DIR TIM_CR1_DIR_Msk /* Direction */
#define TIM_CR1_CMS_Pos (5U)
#define TIM_CR1_CMS_Msk (0x3U << TIM_CR1_CMS_Pos) /* 0x00000060 */
#define TIM_CR1_CMS TIM_CR1_CMS_Msk /* Center-aligned mode selection */
#define TIM_CR1_CMS_0 (0x1U << TIM_CR1_CMS_Pos) /* 0x00000020 */
#define TIM_CR1_CMS_1 (0x2U << TIM_CR1_CMS_Pos) /* 0x00000040 */
#define TIM_CR1_ARPE_Pos (7U)
#define TIM_CR1_ARPE_Msk (0x1U << TIM_CR1_ARPE_Pos) /* 0x00000080 */
#define TIM_CR1_ARPE TIM_CR1_ARPE_Msk /* Auto-reload preload enable */
#define TIM_CR1_CKD_Pos (8U)
#define TIM_CR1_CKD_Msk (0x3U << TIM_CR1_CKD_Pos) /* 0x00000300 */
#define TIM_CR1_CKD TIM_CR1_CKD_Msk /* Clock division */
#define TIM_CR1_CKD_0 (0x1U << TIM_CR1_CKD_Pos) /* 0x00000100 */
#define TIM_CR1_CKD_1 (0x2U << TIM_CR1_CKD_Pos) /* 0x00000200 */

/* TIM_CR2 */
#define TIM_CR2_CCPC_Pos (0U)
#define TIM_CR2_CCPC_Msk (0x1U << TIM_CR2_CCPC_Pos) /* 0x00000001 */
#define TIM_CR2_CCPC TIM_CR2_CCPC_Msk /* Capture/compare preloaded control */
#define TIM_CR2_CCUS_Pos (2U)
#define TIM_CR2_CCUS_Msk (0x1U << TIM_CR2_CCUS_Pos) /* 0x00000004 */
#define TIM_CR2_CCUS TIM_CR2_CCUS_Msk /* Capture/compare control update selection */
#define TIM_CR2_CCDS_Pos (3U)
#define TIM_CR2_CCDS_Msk (0x1U << TIM_CR2_CCDS_Pos) /* 0x00000008 */
#define TIM_CR2_CCDS TIM_CR2_CCDS_Msk /* Capture/compare DMA selection */
#define TIM_CR2_MMS_Pos (4U)
#define TIM_CR2_MMS_Msk (0x7U << TIM_CR2_MMS_Pos) /* 0x00000070 */
#define TIM_CR2_MMS TIM_CR2_MMS_Msk /* Master mode selection */
#define TIM_CR2_MMS_0 (0x1U << TIM_CR2_MMS_Pos) /* 0x00000010 */
#define TIM_CR2_MMS_1 (0x2U << TIM_CR2_MMS_Pos) /* 0x00000020 */
#define TIM_CR2_MMS_2 (0x4U << TIM_CR2_MMS_Pos) /* 0x00000040 */
#define TIM_CR2_TI1S_Pos (7U)
#define TIM_CR2_TI1S_Msk (0x1U << TIM_CR2_TI1S_Pos) /* 0x00000080 */
#define TIM_CR2_TI1S TIM_CR2_TI1S_Msk /* TI1 selection */
#define TIM_CR2_OIS1_Pos (8U)
#define TIM_CR2_OIS1_Msk (0x1U << TIM_CR2_OIS1_Pos) /* 0x00000100 */
#define TIM_CR2_OIS1 TIM_CR2_OIS1_Msk /* Output Idle state 1 */
#define TIM_CR2_OIS1N_Pos (9U)
#define TIM_CR2_OIS1N_Msk (0x1U << TIM_CR2_OIS1N_Pos) /* 0x00000200 */
#define TIM_CR2_OIS1N TIM_CR2_OIS1N_Msk /* Output Idle state 1 */
#define TIM_CR2_OIS2_Pos (10U)
#define TIM_CR2_OIS2_Msk (0x1U << TIM_CR2_OIS2_Pos) /* 0x00000400 */
#define TIM_CR2_OIS2 TIM_CR2_OIS2_Msk /* Output Idle state 2 */
#define TIM_CR2_OIS2N_Pos (11U)
#define TIM_CR2_OIS2N_Msk (0x1U << TIM_CR2_OIS2N_Pos) /* 0x00000800 */
#define TIM_CR2_OIS2N TIM_CR2_OIS2N_Msk /* Output Idle state 2 */
#define TIM_CR2_OIS3_Pos (12U)
#define TIM_CR2_OIS3_Msk (0x1U << TIM_CR2_OIS3_Pos) /* 0x00001000 */
#define TIM_CR2_OIS3 TIM_CR2_OIS3_Msk /* Output Idle state 3 */
#define TIM_CR2_OIS3N_Pos (13U)
#define TIM_CR2_OIS3N_Msk (0x1U << TIM_CR2_OIS3N_Pos) /* 0x00002000 */
#define TIM_CR2_OIS3N TIM_CR2_OIS3N_Msk /* Output Idle state 3 */
#define TIM_CR2_OIS4_Pos (14U)
#define TIM_CR2_OIS4_Msk (0x1U << TIM_CR2_OIS4_Pos) /* 0x00004000 */
#define TIM_CR2_OIS4 TIM_CR2_OIS4_Msk /* Output Idle state 4 */

/* TIM_SMCR */
#define TIM_SMCR_SMS_Pos (0U)
#define TIM_SMCR_SMS_Msk (0x7U << TIM_SMCR_SMS_Pos) /* 0x00000007 */
#define TIM_SMCR_SMS TIM_SMCR_SMS_Msk /* Slave mode selection */
#define TIM_SMCR_SMS_0 (0x1U << TIM_SMCR_SMS_Pos) /* 0x00000001 */
#define TIM_SMCR_SMS_1 (0x2U << TIM_SMCR_SMS_Pos) /* 0x00000002 */
#define TIM_SMCR_SMS_2 (0x4U << TIM_SMCR_SMS_Pos) /* 0x00000004 */
#define TIM_SMCR_TS_Pos (4U)
#define TIM_SMCR_TS_Msk (0x7U << TIM_SMCR_TS_Pos) /* 0x00000070 */
#define TIM_SMCR_TS TIM_SMCR_TS_Msk /* Trigger selection */
#define TIM_SMCR_TS_0 (0x1U << TIM_SMCR_TS_Pos) /* 0x00000010 */
#define TIM_SMCR_TS_1 (0x2U << TIM_SMCR_TS_Pos) /* 0x00000020 */
#define TIM_SMCR_TS_2 (0x4U << TIM_SMCR_TS_Pos) /* 0x00000040 */
#define TIM_SMCR_MSM_Pos (7U)
#define TIM_SMCR_MSM_Msk (0x1U << TIM_SMCR_MSM_Pos) /* 0x00000080 */
#define TIM_SMCR_MSM TIM_SMCR_MSM_Msk /* Master/Slave mode */
#define TIM_SMCR_ETF_Pos (8U)
#define TIM_SMCR_ETF_Msk (0xfU << TIM_SMCR_ETF_Pos) /* 0x00000F00 */
#define TIM_SMCR_ETF TIM_SMCR_ETF_Msk /* External trigger filter */
#define TIM_SMCR_ETF_0 (0x1U << TIM_SMCR_ETF_Pos) /* 0x00000100 */
#define TIM_SMCR_ETF_1 (0x2U << TIM_SMCR_ETF_Pos) /* 0x00000200 */
#define TIM_SMCR_ETF_2 (0x4U << TIM_SMCR_ETF_Pos) /* 0x00000400 */
#define TIM_SMCR_ETF_3 (0x8U << TIM_SMCR_ETF_Pos) /* 0x00000800 */
#define TIM_SMCR_ETPS_Pos (12U)
#define TIM_SMCR_ETPS_Msk (0x3U << TIM_SMCR_ETPS_Pos) /* 0x00003000 */
#define TIM_SMCR_ETPS TIM_SMCR_ETPS_Msk /* External trigger prescaler */
#define TIM_SMCR_ETPS_0 (0x1U << TIM_SMCR_ETPS_Pos) /* 0x00001000 */
#define TIM_SMCR_ETPS_1 (0x2U << TIM_SMCR_ETPS_Pos) /* 0x00002000 */
#define TIM_SMCR_ECE_Pos (14U)
#define TIM_SMCR_ECE_Msk (0x1U << TIM_SMCR_ECE_Pos) /* 0x00004000 */
#define TIM_SMCR_ECE TIM_SMCR_ECE_Msk /* External clock enable */
#define TIM_SMCR_ETP_Pos (15U)
#define TIM_SMCR_ETP_Msk (0x1U << TIM_SMCR_ETP_Pos) /* 0x00008000 */
#define TIM_SMCR_ETP TIM_SMCR_ETP_Msk /* External trigger polarity */

/* TIM_DIER */
#define TIM_DIER_UIE_Pos (0U)
#define TIM_DIER_UIE_Msk (0x1U << TIM_DIER_UIE_Pos) /* 0x00000001 */
#define TIM_DIER_UIE TIM_DIER_UIE_Msk /* Update interrupt enable */
#define TIM_DIER_CC1IE_Pos (1U)
#define TIM_DIER_CC1IE_Msk (0x1U << TIM_DIER_CC1IE_Pos) /* 0x00000002 */
#define TIM_DIER_CC1IE TIM_DIER_CC1IE_Msk /* Capture/Compare 1 interrupt enable */
#define TIM_DIER_CC2IE_Pos (2U)
#define TIM_DIER_CC2IE_Msk (0x1U << TIM_DIER_CC2IE_Pos) /* 0x00000004 */
#define TIM_DIER_CC2IE TIM_DIER_CC2IE_Msk /* Capture/Compare 2 interrupt enable */
#define TIM_DIER_CC3IE_Pos (3U)
#define TIM_DIER_CC3IE_Msk (0x1U << TIM_DIER_CC3IE_Pos) /* 0x00000008 */
#define TIM_DIER_CC3IE TIM_DIER_CC3IE_Msk /* Capture/Compare 3 interrupt enable */
#define TIM_DIER_CC4IE_Pos (4U)
#define TIM_DIER_CC4IE_Msk (0x1U << TIM_DIER_CC4IE_Pos) /* 0x00000010 */
#define TIM_DIER_CC4IE TIM_DIER_CC4IE_Msk /* Capture/Compare 4 interrupt enable */
#define TIM_DIER_COMIE_Pos (5U)
#define TIM_DIER_COMIE_Msk (0x1U << TIM_DIER_COMIE_Pos) /* 0x00000020 */
#define TIM_DIER_COMIE TIM_DIER_COMIE_Msk /* COM interrupt enable */
#define TIM_DIER_TIE_Pos (6U)
#define TIM_DIER_TIE_Msk (0x1U << TIM_DIER_TIE_Pos) /* 0x00000040 */
#define TIM_DIER_TIE TIM_DIER_TIE_Msk /* Trigger interrupt enable */
#define TIM_DIER_BIE_Pos (7U)
#define TIM_DIER_BIE_Msk (0x1U << TIM_DIER_BIE_Pos) /* 0x00000080 */
#define TIM_DIER_BIE TIM_DIER_BIE_Msk /* Break interrupt enable */
#define TIM_DIER_UDE_Pos (8U)
#define TIM_DIER_UDE_Msk (0x1U << TIM_DIER_UDE_Pos) /* 0x00000100 */
#define TIM_DIER_UDE TIM_DIER_UDE_Msk /* Update DMA request enable */
#define TIM_DIER_CC1DE_Pos (9U)
#define TIM_DIER_CC1DE_Msk (0x1U << TIM_DIER_CC1DE_Pos) /* 0x00000200 */
#define TIM_DIER_CC1DE TIM_DIER_CC1DE_Msk /* Capture/Compare 1 DMA request enable */
#define TIM_DIER_CC2DE_Pos (10U)
#define TIM_DIER_CC2DE_Msk (0x1U << TIM_DIER_CC2DE_Pos) /* 0x00000400 */
#define TIM_DIER_CC2DE TIM_DIER_CC2DE_Msk /* Capture/Compare 2 DMA request enable */
#define TIM_DIER_CC3DE_Pos (11U)
#define TIM_DIER_CC3DE_Msk (0x1U << TIM_DIER_CC3DE_Pos) /* 0x00000800 */
#define TIM_DIER_CC3DE TIM_DIER_CC3DE_Msk /* Capture/Compare 3 DMA request enable */
#define TIM_DIER_CC4DE_Pos (12U)
#define TIM_DIER_CC4DE_Msk (0x1U << TIM_DIER_CC4DE_Pos) /* 0x00001000 */
#define TIM_DIER_CC4DE TIM_DIER_CC4DE_Msk /* Capture/Compare 4 DMA request enable */
#define TIM_DIER_COMDE_Pos (13U)
#define TIM_DIER_COMDE_Msk (0x1U << TIM_DIER_COMDE_Pos) /* 0x00002000 */
#define TIM_DIER_COMDE TIM_DIER_COMDE_Msk /* COM DMA request enable */
#define TIM_DIER_TDE_Pos (14U)
#define TIM_DIER_TDE_Msk (0x1U << TIM_DIER_TDE_Pos) /* 0x00004000 */
#define TIM_DIER_TDE TIM_DIER_TDE_Msk /* Trigger DMA request enable */

/* TIM_SR */
#define TIM_SR_UIF_Pos (0U)
#define TIM_SR_UIF_Msk (0x1U << TIM_SR_UIF_Pos) /* 0x00000001 */
#define TIM_SR_UIF TIM_SR_UIF_Msk /* Update interrupt flag */
#define TIM_SR_CC1IF_Pos (1U)
#define TIM_SR_CC1IF_Msk (0x1U << TIM_SR_CC1IF_Pos) /* 0x00000002 */
#define TIM_SR_CC1IF TIM_SR_CC1IF_Msk /* Capture/compare 1 interrupt flag */
#define TIM_SR_CC2IF_Pos (2U)
#define TIM_SR_CC2IF_Msk (0x1U << TIM_SR_CC2IF_Pos) /* 0x00000004 */
#define TIM_SR_CC2IF TIM_SR_CC2IF_Msk /* Capture/Compare 2 interrupt flag */
#define TIM_SR_CC3IF_Pos (3U)
#define TIM_SR_CC3IF_Msk (0x1U << TIM_SR_CC3IF_Pos) /* 0x00000008 */
#define TIM_SR_CC3IF TIM_SR_CC3IF_Msk /* Capture/Compare 3 interrupt flag */
#define TIM_SR_CC4IF_Pos (4U)
#define TIM_SR_CC4IF_Msk (0x1U << TIM_SR_CC4IF_Pos) /* 0x00000010 */
#define TIM_SR_CC4IF TIM_SR_CC4IF_Msk /* Capture/Compare 4 interrupt flag */
#define TIM_SR_COMIF_Pos (5U)
#define TIM_SR_COMIF_Msk (0x1U << TIM_SR_COMIF_Pos) /* 0x00000020 */
#define TIM_SR_COMIF TIM_SR_COMIF_Msk /* COM interrupt flag */
#define TIM_SR_TIF_Pos (6U)
#define TIM_SR_TIF_Msk (0x1U << TIM_SR_TIF_Pos) /* 0x00000040 */
#define TIM_SR_TIF TIM_SR_TIF_Msk /* Trigger interrupt flag */
#define TIM_SR_BIF_Pos (7U)
#define TIM_SR_BIF_Msk (0x1U << TIM_SR_BIF_Pos) /* 0x00000080 */
#define TIM_SR_BIF TIM_SR_BIF_Msk /* Break interrupt flag */
#define TIM_SR_CC1OF_Pos (9U)
#define TIM_SR_CC1OF_Msk (0x1U << TIM_SR_CC1OF_Pos) /* 0x00000200 */
#define TIM_SR_CC1OF TIM_SR_CC1OF_Msk /* Capture/Compare 1 overcapture flag */
#define TIM_SR_CC2OF_Pos (10U)
#define TIM_SR_CC2OF_Msk (0x1U << TIM_SR_CC2OF_Pos) /* 0x00000400 */
#define TIM_SR_CC2OF TIM_SR_CC2OF_Msk /* Capture/compare 2 overcapture flag */
#define TIM_SR_CC3OF_Pos (11U)
#define TIM_SR_CC3OF_Msk (0x1U << TIM_SR_CC3OF_Pos) /* 0x00000800 */
#define TIM_SR_CC3OF TIM_SR_CC3OF_Msk /* Capture/Compare 3 overcapture flag */
#define TIM_SR_CC4OF_Pos (12U)
#define TIM_SR_CC4OF_Msk (0x1U << TIM_SR_CC4OF_Pos) /* 0x00001000 */
#define TIM_SR_CC4OF TIM_SR_CC4OF_Msk /* Capture/Compare 4 overcapture flag */

/* TIM_EGR */
#define TIM_EGR_UG_Pos (0U)
#define TIM_EGR_UG_Msk (0x1U << TIM_EGR_UG_Pos) /* 0x00000001 */
#define TIM_EGR_UG TIM_EGR_UG_Msk /* Update generation */
#define TIM_EGR_CC1G_Pos (1U)
#define TIM_EGR_CC1G_Msk (0x1U << TIM_EGR_CC1G_Pos) /* 0x00000002 */
#define TIM_EGR_CC1G TIM_EGR_CC1G_Msk /* Capture/compare 1 generation */
#define TIM_EGR_CC2G_Pos (2U)
#define TIM_EGR_CC2G_Msk (0x1U << TIM_EGR_CC2G_Pos) /* 0x00000004 */
#define TIM_EGR_CC2G TIM_EGR_CC2G_Msk /* Capture/compare 2 generation */
#define TIM_EGR_CC3G_Pos (3U)
#define TIM_EGR_CC3G_Msk (0x1U << TIM_EGR_CC3G_Pos) /* 0x00000008 */
#define TIM_EGR_CC3G TIM_EGR_CC3G_Msk /* Capture/compare 3 generation */
#define TIM_EGR_CC4G_Pos (4U)
#define TIM_EGR_CC4G_Msk (0x1U << TIM_EGR_CC4G_Pos) /* 0x00000010 */
#define TIM_EGR_CC4G TIM_EGR_CC4G_Msk /* Capture/compare 4 generation */
#define TIM_EGR_COMG_Pos (5U)
#define TIM_EGR_COMG_Msk (0x1U << TIM_EGR_COMG_Pos) /* 0x00000020 */
#define TIM_EGR_COMG TIM_EGR_COMG_Msk /* Capture/Compare control update generation */
#define TIM_EGR_TG_Pos (6U)
#define TIM_EGR_TG_Msk (0x1U << TIM_EGR_TG_Pos) /* 0x00000040 */
#define TIM_EGR_TG TIM_EGR_TG_Msk /* Trigger generation */
#define TIM_EGR_BG_Pos (7U)
#define TIM_EGR_BG_Msk (0x1U << TIM_EGR_BG_Pos) /* 0x00000080 */
#define TIM_EGR_BG TIM_EGR_BG_Msk /* Break generation */

/* TIM_CCMR1 */
#define TIM_CCMR1_CC1S_Pos (0U)
#define TIM_CCMR1_CC1S_Msk (0x3U << TIM_CCMR1_CC1S_Pos) /* 0x00000003 */
#define TIM_CCMR1_CC1S TIM_CCMR1_CC1S_Msk /* Capture/Compare 1 selection */
#define TIM_CCMR1_CC1S_0 (0x1U << TIM_CCMR1_CC1S_Pos) /* 0x00000001 */
#define TIM_CCMR1_CC1S_1 (0x2U << TIM_CCMR1_CC1S_Pos) /* 0x00000002 */
#define TIM_CCMR1_IC1PSC_Pos (2U)
#define TIM_CCMR1_IC1PSC_Msk (0x3U << TIM_CCMR1_IC1PSC_Pos) /* 0x0000000C */
#define TIM_CCMR1_IC1PSC TIM_CCMR1_IC1PSC_Msk /* Input capture 1 prescaler */
#define TIM_CCMR1_IC1PSC_0 (0x1U << TIM_CCMR1_IC1PSC_Pos) /* 0x00000004 */
#define TIM_CCMR1_IC1PSC_1 (0x2U << TIM_CCMR1_IC1PSC_Pos) /* 0x00000008 */
#define TIM_CCMR1_OC1FE_Pos (2U)
#define TIM_CCMR1_OC1FE_Msk (0x1U << TIM_CCMR1_OC1FE_Pos) /* 0x00000004 */
#define TIM_CCMR1_OC1FE TIM_CCMR1_OC1FE_Msk /* Output Compare 1 fast enable */
#define TIM_CCMR1_OC1PE_Pos (3U)
#define TIM_CCMR1_OC1PE_Msk (0x1U << TIM_CCMR1_OC1PE_Pos) /* 0x00000008 */
#define TIM_CCMR1_OC1PE TIM_CCMR1_OC1PE_Msk /* Output Compare 1 preload enable */
#define TIM_CCMR1_IC1F_Pos (4U)
#define TIM_CCMR1_IC1F_Msk (0xfU << TIM_CCMR1_IC1F_Pos) /* 0x000000F0 */
#define TIM_CCMR1_IC1F TIM_CCMR1_IC1F_Msk /* Input capture 1 filter */
#define TIM_CCMR1_IC1F_0 (0x1U << TIM_CCMR1_IC1F_Pos) /* 0x00000010 */
#define TIM_CCMR1_IC1F_1 (0x2U << TIM_CCMR1_IC1F_Pos) /* 0x00000020 */
#define TIM_CCMR1_IC1F_2 (0x4U << TIM_CCMR1_IC1F_Pos) /* 0x00000040 */
#define TIM_CCMR1_IC1F_3 (0x8U << TIM_CCMR1_IC1F_Pos) /* 0x00000080 */
#define TIM_CCMR1_OC1M_Pos (4U)
#define TIM_CCMR1_OC1M_Msk (0x7U << TIM_CCMR1_OC1M_Pos) /* 0x00000070 */
#define TIM_CCMR1_OC1M TIM_CCMR1_OC1M_Msk /* Output Compare 1 mode */
#define TIM_CCMR1_OC1M_0 (0x1U << TIM_CCMR1_OC1M_Pos) /* 0x00000010 */
#define TIM_CCMR1_OC1M_1 (0x2U << TIM_CCMR1_OC1M_Pos) /* 0x00000020 */
#define TIM_CCMR1_OC1M_2 (0x4U << TIM_CCMR1_OC1M_Pos) /* 0x00000040 */
#define TIM_CCMR1_OC1CE_Pos (7U)
#define TIM_CCMR1_OC1CE_Msk (0x1U << TIM_CCMR1_OC1CE_Pos) /* 0x00000080 */
#define TIM_CCMR1_OC1CE TIM_CCMR1_OC1CE_Msk /* Output Compare 1 clear enable */
#define TIM_CCMR1_CC2S_Pos (8U)
#define TIM_CCMR1_CC2S_Msk (0x3U << TIM_CCMR1_CC2S_Pos) /* 0x00000300 */
#define TIM_CCMR1_CC2S TIM_CCMR1_CC2S_Msk /* Capture/Compare 2 selection */
#define TIM_CCMR1_CC2S_0 (0x1U << TIM_CCMR1_CC2S_Pos) /* 0x00000100 */
#define TIM_CCMR1_CC2S_1 (0x2U << TIM_CCMR1_CC2S_Pos) /* 0x00000200 */
#define TIM_CCMR1_IC2PCS_Pos (10U)
#define TIM_CCMR1_IC2PCS_Msk (0x3U << TIM_CCMR1_IC2PCS_Pos) /* 0x00000C00 */
#define TIM_CCMR1_IC2PCS TIM_CCMR1_IC2PCS_Msk /* Input capture 2 prescaler */
#define TIM_CCMR1_IC2PCS_0 (0x1U << TIM_CCMR1_IC2PCS_Pos) /* 0x00000400 */
#define TIM_CCMR1_IC2PCS_1 (0x2U << TIM_CCMR1_IC2PCS_Pos) /* 0x00000800 */
#define TIM_CCMR1_IC2PSC_Pos (10U)
#define TIM_CCMR1_IC2PSC_Msk (0x3U << TIM_CCMR1_IC2PSC_Pos) /* 0x00000C00 */
#define TIM_CCMR1_IC2PSC TIM_CCMR1_IC2PSC_Msk /* Input capture 2 prescaler */
#define TIM_CCMR1_IC2PSC_0 (0x1U << TIM_CCMR1_IC2PSC_Pos) /* 0x00000400 */
#define TIM_CCMR1_IC2PSC_1 (0x2U << TIM_CCMR1_IC2PSC_Pos) /* 0x00000800 */
#define TIM_CCMR1_OC2FE_Pos (10U)
#define TIM_CCMR1_OC2FE_Msk (0x1U << TIM_CCMR1_OC2FE_Pos) /* 0x00000400 */
#define TIM_CCMR1_OC2FE TIM_CCMR1_OC2FE_Msk /* Output Compare 2 fast enable */
#define TIM_CCMR1_OC2PE_Pos (11U)
#define TIM_CCMR1_OC2PE_Msk (0x1U << TIM_CCMR1_OC2PE_Pos) /* 0x00000800 */
#define TIM_CCMR1_OC2PE TIM_CCMR1_OC2PE_Msk /* Output Compare 2 preload enable */
#define TIM_CCMR1_IC2F_Pos (12U)
#define TIM_CCMR1_IC2F_Msk (0xfU << TIM_CCMR1_IC2F_Pos) /* 0x0000F000 */
#define TIM_CCMR1_IC2F TIM_CCMR1_IC2F_Msk /* Input capture 2 filter */
#define TIM_CCMR1_IC2F_0 (0x1U << TIM_CCMR1_IC2F_Pos) /* 0x00001000 */
#define TIM_CCMR1_IC2F_1 (0x2U << TIM_CCMR1_IC2F_Pos) /* 0x00002000 */
#define TIM_CCMR1_IC2F_2 (0x4U << TIM_CCMR1_IC2F_Pos) /* 0x00004000 */
#define TIM_CCMR1_IC2F_3 (0x8U << TIM_CCMR1_IC2F_Pos) /* 0x00008000 */
#define TIM_CCMR1_OC2M_Pos (12U)
#define TIM_CCMR1_OC2M_Msk (0x7U << TIM_CCMR1_OC2M_Pos) /* 0x00007000 */
#define TIM_CCMR1_OC2M TIM_CCMR1_OC2M_Msk /* Output Compare 2 mode */
#define TIM_CCMR1_OC2M_0 (0x1U << TIM_CCMR1_OC2M_Pos) /* 0x00001000 */
#define TIM_CCMR1_OC2M_1 (0x2U << TIM_CCMR1_OC2M_Pos) /* 0x00002000 */
#define TIM_CCMR1_OC2M_2 (0x4U << TIM_CCMR1_OC2M_Pos) /* 0x00004000 */
#define TIM_CCMR1_OC2CE_Pos (15U)
#define TIM_CCMR1_OC2CE_Msk (0x1U << TIM_CCMR1_OC2CE_Pos) /* 0x00008000 */
#define TIM_CCMR1_OC2CE TIM_CCMR1_OC2CE_Msk /* Output Compare 2 clear enable */

/* TIM_CCMR2 */
#define TIM_CCMR2_CC3S_Pos (0U)
#define TIM_CCMR2_CC3S_Msk (0x3U << TIM_CCMR2_CC3S_Pos) /* 0x00000003 */
#define TIM_CCMR2_CC3S TIM_CCMR2_CC3S_Msk /* Capture/Compare 3 selection */
#define TIM_CCMR2_CC3S_0 (0x1U << TIM_CCMR2_CC3S_Pos) /* 0x00000001 */
#define TIM_CCMR2_CC3S_1 (0x2U << TIM_CCMR2_CC3S_Pos) /* 0x00000002 */
#define TIM_CCMR2_IC3PSC_Pos (2U)
#define TIM_CCMR2_IC3PSC_Msk (0x3U << TIM_CCMR2_IC3PSC_Pos) /* 0x0000000C */
#define TIM_CCMR2_IC3PSC TIM_CCMR2_IC3PSC_Msk /* Input capture 3 prescaler */
#define TIM_CCMR2_IC3PSC_0 (0x1U << TIM_CCMR2_IC3PSC_Pos) /* 0x00000004 */
#define TIM_CCMR2_IC3PSC_1 (0x2U << TIM_CCMR2_IC3PSC_Pos) /* 0x00000008 */
#define TIM_CCMR2_OC3FE_Pos (2U)
#define TIM_CCMR2_OC3FE_Msk (0x1U << TIM_CCMR2_OC3FE_Pos) /* 0x00000004 */
#define TIM_CCMR2_OC3FE TIM_CCMR2_OC3FE_Msk /* Output compare 3 fast enable */
#define TIM_CCMR2_OC3PE_Pos (3U)
#define TIM_CCMR2_OC3PE_Msk (0x1U << TIM_CCMR2_OC3PE_Pos) /* 0x00000008 */
#define TIM_CCMR2_OC3PE TIM_CCMR2_OC3PE_Msk /* Output compare 3 preload enable */
#define TIM_CCMR2_IC3F_Pos (4U)
#define TIM_CCMR2_IC3F_Msk (0xfU << TIM_CCMR2_IC3F_Pos) /* 0x000000F0 */
#define TIM_CCMR2_IC3F TIM_CCMR2_IC3F_Msk /* Input capture 3 filter */
#define TIM_CCMR2_IC3F_0 (0x1U << TIM_CCMR2_IC3F_Pos) /* 0x00000010 */
#define TIM_CCMR2_IC3F_1 (0x2U << TIM_CCMR2_IC3F_Pos) /* 0x00000020 */
#define TIM_CCMR2_IC3F_2 (0x4U << TIM_CCMR2_IC3F_Pos) /* 0x00000040 */
#define TIM_CCMR2_IC3F_3 (0x8U << TIM_CCMR2_IC3F_Pos) /* 0x00000080 */
#define TIM_CCMR2_OC3M_Pos (4U)
#define TIM_CCMR2_OC3M_Msk (0x7U << TIM_CCMR2_OC3M_Pos) /* 0x00000070 */
#define TIM_CCMR2_OC3M TIM_CCMR2_OC3M_Msk /* Output compare 3 mode */
#define TIM_CCMR2_OC3M_0 (0x1U << TIM_CCMR2_OC3M_Pos) /* 0x00000010 */
#define TIM_CCMR2_OC3M_1 (0x2U << TIM_CCMR2_OC3M_Pos) /* 0x00000020 */
#define TIM_CCMR2_OC3M_2 (0x4U << TIM_CCMR2_OC3M_Pos) /* 0x00000040 */
#define TIM_CCMR2_OC3CE_Pos (7U)
#define TIM_CCMR2_OC3CE_Msk (0x1U << TIM_CCMR2_OC3CE_Pos) /* 0x00000080 */
#define TIM_CCMR2_OC3CE TIM_CCMR2_OC3CE_Msk /* Output compare 3 clear enable */
#define TIM_CCMR2_CC4S_Pos (8U)
#define TIM_CCMR2_CC4S_Msk (0x3U << TIM_CCMR2_CC4S_Pos) /* 0x00000300 */
#define TIM_CCMR2_CC4S TIM_CCMR2_CC4S_Msk /* Capture/Compare 4 selection */
#define TIM_CCMR2_CC4S_0 (0x1U << TIM_CCMR2_CC4S_Pos) /* 0x00000100 */
#define TIM_CCMR2_CC4S_1 (0x2U << TIM_CCMR2_CC4S_Pos) /* 0x00000200 */
#define TIM_CCMR2_IC4PSC_Pos (10U)
#define TIM_CCMR2_IC4PSC_Msk (0x3U << TIM_CCMR2_IC4PSC_Pos) /* 0x00000C00 */
#define TIM_CCMR2_IC4PSC TIM_CCMR2_IC4PSC_Msk /* Input capture 4 prescaler */
#define TIM_CCMR2_IC4PSC_0 (0x1U << TIM_CCMR2_IC4PSC_Pos) /* 0x00000400 */
#define TIM_CCMR2_IC4PSC_1 (0x2U << TIM_CCMR2_IC4PSC_Pos) /* 0x00000800 */
#define TIM_CCMR2_OC4FE_Pos (10U)
#define TIM_CCMR2_OC4FE_Msk (0x1U << TIM_CCMR2_OC4FE_Pos) /* 0x00000400 */
#define TIM_CCMR2_OC4FE TIM_CCMR2_OC4FE_Msk /* Output compare 4 fast enable */
#define TIM_CCMR2_OC4PE_Pos (11U)
#define TIM_CCMR2_OC4PE_Msk (0x1U << TIM_CCMR2_OC4PE_Pos) /* 0x00000800 */
#define TIM_CCMR2_OC4PE TIM_CCMR2_OC4PE_Msk /* Output compare 4 preload enable */
#define TIM_CCMR2_IC4F_Pos (12U)
#define TIM_CCMR2_IC4F_Msk (0xfU << TIM_CCMR2_IC4F_Pos) /* 0x0000F000 */
#define TIM_CCMR2_IC4F TIM_CCMR2_IC4F_Msk /* Input capture 4 filter */
#define TIM_CCMR2_IC4F_0 (0x1U << TIM_CCMR2_IC4F_Pos) /* 0x00001000 */
#define TIM_CCMR2_IC4F_1 (0x2U << TIM_CCMR2_IC4F_Pos) /* 0x00002000 */
#define TIM_CCMR2_IC4F_2 (0x4U << TIM_CCMR2_IC4F_Pos) /* 0x00004000 */
#define TIM_CCMR2_IC4F_3 (0x8U << TIM_CCMR2_IC4F_Pos) /* 0x00008000 */
#define TIM_CCMR2_OC4M_Pos (12U)
#define TIM_CCMR2_OC4M_Msk (0x7U << TIM_CCMR2_OC4M_Pos) /* 0x00007000 */
#define TIM_CCMR2_OC4M TIM_CCMR2_OC4M_Msk /* Output compare 4 mode */
#define TIM_CCMR2_OC4M_0 (0x1U << TIM_CCMR2_OC4M_Pos) /* 0x00001000 */
#define TIM_CCMR2_OC4M_1 (0x2U << TIM_CCMR2_OC4M_Pos) /* 0x00002000 */
#define TIM_CCMR2_OC4M_2 (0x4U << TIM_CCMR2_OC4M_Pos) /* 0x00004000 */
#define TIM_CCMR2_OC4CE_Pos (15U)
#define TIM_CCMR2_OC4CE_Msk (0x1U << TIM_CCMR2_OC4CE_Pos) /* 0x00008000 */
#define TIM_CCMR2_OC4CE TIM_CCMR2_OC4CE_Msk /* Output compare 4 clear enable */

/* TIM_CCER */
#define TIM_CCER_CC1E_Pos (0U)
#define TIM_CCER_CC1E_Msk (0x1U << TIM_CCER_CC1E_Pos) /* 0x00000001 */
#define TIM_CCER_CC1E TIM_CCER_CC1E_Msk /* Capture/Compare 1 output enable */
#define TIM_CCER_CC1P_Pos (1U)
#define TIM_CCER_CC1P_Msk (0x1U << TIM_CCER_CC1P_Pos) /* 0x00000002 */
#define TIM_CCER_CC1P TIM_CCER_CC1P_Msk /* Capture/Compare 1 output Polarity */
#define TIM_CCER_CC1NE_Pos (2U)
#define TIM_CCER_CC1NE_Msk (0x1U << TIM_CCER_CC1NE_Pos) /* 0x00000004 */
#define TIM_CCER_CC1NE TIM_CCER_CC1NE_Msk /* Capture/Compare 1 complementary output enable */
#define TIM_CCER_CC1NP_Pos (3U)
#define TIM_CCER_CC1NP_Msk (0x1U << TIM_CCER_CC1NP_Pos) /* 0x00000008 */
#define TIM_CCER_CC1NP TIM_CCER_CC1NP_Msk /* Capture/Compare 1 output Polarity */
#define TIM_CCER_CC2E_Pos (4U)
#define TIM_CCER_CC2E_Msk (0x1U << TIM_CCER_CC2E_Pos) /* 0x00000010 */
#define TIM_CCER_CC2E TIM_CCER_CC2E_Msk /* Capture/Compare 2 output enable */
#define TIM_CCER_CC2P_Pos (5U)
#define TIM_CCER_CC2P_Msk (0x1U << TIM_CCER_CC2P_Pos) /* 0x00000020 */
#define TIM_CCER_CC2P TIM_CCER_CC2P_Msk /* Capture/Compare 2 output Polarity */
#define TIM_CCER_CC2NE_Pos (6U)
#define TIM_CCER_CC2NE_Msk (0x1U << TIM_CCER_CC2NE_Pos) /* 0x00000040 */
#define TIM_CCER_CC2NE TIM_CCER_CC2NE_Msk /* Capture/Compare 2 complementary output enable */
#define TIM_CCER_CC2NP_Pos (7U)
#define TIM_CCER_CC2NP_Msk (0x1U << TIM_CCER_CC2NP_Pos) /* 0x00000080 */
#define TIM_CCER_CC2NP TIM_CCER_CC2NP_Msk /* Capture/Compare 2 output Polarity */
#define TIM_CCER_CC3E_Pos (8U)
#define TIM_CCER_CC3E_Msk (0x1U << TIM_CCER_CC3E_Pos) /* 0x00000100 */
#define TIM_CCER_CC3E TIM_CCER_CC3E_Msk /* Capture/Compare 3 output enable */
#define TIM_CCER_CC3P_Pos (9U)
#define TIM_CCER_CC3P_Msk (0x1U << TIM_CCER_CC3P_Pos) /* 0x00000200 */
#define TIM_CCER_CC3P TIM_CCER_CC3P_Msk /* Capture/Compare 3 output Polarity */
#define TIM_CCER_CC3NE_Pos (10U)
#define TIM_CCER_CC3NE_Msk (0x1U << TIM_CCER_CC3NE_Pos) /* 0x00000400 */
#define TIM_CCER_CC3NE TIM_CCER_CC3NE_Msk /* Capture/Compare 3 complementary output enable */
#define TIM_CCER_CC3NP_Pos (11U)
#define TIM_CCER_CC3NP_Msk (0x1U << TIM_CCER_CC3NP_Pos) /* 0x00000800 */
#define TIM_CCER_CC3NP TIM_CCER_CC3NP_Msk /* Capture/Compare 3 output Polarity */
#define TIM_CCER_CC4E_Pos (12U)
#define TIM_CCER_CC4E_Msk (0x1U << TIM_CCER_CC4E_Pos) /* 0x00001000 */
#define TIM_CCER_CC4E TIM_CCER_CC4E_Msk /* Capture/Compare 4 output enable */
#define TIM_CCER_CC4P_Pos (13U)
#define TIM_CCER_CC4P_Msk (0x1U << TIM_CCER_CC4P_Pos) /* 0x00002000 */
#define TIM_CCER_CC4P TIM_CCER_CC4P_Msk /* Capture/Compare 3 output Polarity */

/* TIM_CNT */
#define TIM_CNT_CNT_Pos (0U)
#define TIM_CNT_CNT_Msk (0xffffU << TIM_CNT_CNT_Pos) /* 0x0000FFFF */
#define TIM_CNT_CNT TIM_CNT_CNT_Msk /* counter value */

/* TIM_PSC */
#define TIM_PSC_PSC_Pos (0U)
#define TIM_PSC_PSC_Msk (0xffffU << TIM_PSC_PSC_Pos) /* 0x0000FFFF */
#define TIM_PSC_PSC TIM_PSC_PSC_Msk /* Prescaler value */

/* TIM_ARR */
#define TIM_ARR_ARR_Pos (0U)
#define TIM_ARR_ARR_Msk (0xffffU << TIM_ARR_ARR_Pos) /* 0x0000FFFF */
#define TIM_ARR_ARR TIM_ARR_ARR_Msk /* Auto-reload value */

/* TIM_CCR1 */
#define TIM_CCR1_CCR1_Pos (0U)
#define TIM_CCR1_CCR1_Msk (0xffffU << TIM_CCR1_CCR1_Pos) /* 0x0000FFFF */
#define TIM_CCR1_CCR1 TIM_CCR1_CCR1_Msk /* Capture/Compare 1 value */

/* TIM_CCR2 */
#define TIM_CCR2_CCR2_Pos (0U)
#define TIM_CCR2_CCR2_Msk (0xffffU << TIM_CCR2_CCR2_Pos) /* 0x0000FFFF */
#define TIM_CCR2_CCR2 TIM_CCR2_CCR2_Msk /* Capture/Compare 2 value */

/* TIM_CCR3 */
#define TIM_CCR3_CCR3_Pos (0U)
#define TIM_CCR3_CCR3_Msk (0xffffU << TIM_CCR3_CCR3_Pos) /* 0x0000FFFF */
#define TIM_CCR3_CCR3 TIM_CCR3_CCR3_Msk /* Capture/Compare value */

/* TIM_CCR4 */
#define TIM_CCR4_CCR4_Pos (0U)
#define TIM_CCR4_CCR4_Msk (0xffffU << TIM_CCR4_CCR4_Pos) /* 0x0000FFFF */
#define TIM_CCR4_CCR4 TIM_CCR4_CCR4_Msk /* Capture/Compare value */

/* TIM_BDTR */
#define TIM_BDTR_DTG_Pos (0U)
#define TIM_BDTR_DTG_Msk (0xffU << TIM_BDTR_DTG_Pos) /* 0x000000FF */
#define TIM_BDTR_DTG TIM_BDTR_DTG_Msk /* Dead-time generator setup */
#define TIM_BDTR_DTG_0 (0x1U << TIM_BDTR_DTG_Pos) /* 0x00000001 */
#define TIM_BDTR_DTG_1 (0x2U << TIM_BDTR_DTG_Pos) /* 0x00000002 */
#define TIM_BDTR_DTG_2 (0x4U << TIM_BDTR_DTG_Pos) /* 0x00000004 */
#define TIM_BDTR_DTG_3 (0x8U << TIM_BDTR_DTG_Pos) /* 0x00000008 */
#define TIM_BDTR_DTG_4 (0x10U << TIM_BDTR_DTG_Pos) /* 0x00000010 */
#define TIM_BDTR_DTG_5 (0x20U << TIM_BDTR_DTG_Pos) /* 0x00000020 */
#define TIM_BDTR_DTG_6 (0x40U << TIM_BDTR_DTG_Pos) /* 0x00000040 */
#define TIM_BDTR_DTG_7 (0x80U << TIM_BDTR_DTG_Pos) /* 0x00000080 */
#define TIM_BDTR_LOCK_Pos (8U)
#define TIM_BDTR_LOCK_Msk (0x3U << TIM_BDTR_LOCK_Pos) /* 0x00000300 */
#define TIM_BDTR_LOCK TIM_BDTR_LOCK_Msk /* Lock configuration */
#define TIM_BDTR_LOCK_0 (0x1U << TIM_BDTR_LOCK_Pos) /* 0x00000100 */
#define TIM_BDTR_LOCK_1 (0x2U << TIM_BDTR_LOCK_Pos) /* 0x00000200 */
#define TIM_BDTR_OSSI_Pos (10U)
#define TIM_BDTR_OSSI_Msk (0x1U << TIM_BDTR_OSSI_Pos) /* 0x00000400 */
#define TIM_BDTR_OSSI TIM_BDTR_OSSI_Msk /* Off-state selection for Idle mode */
#define TIM_BDTR_OSSR_Pos (11U)
#define TIM_BDTR_OSSR_Msk (0x1U << TIM_BDTR_OSSR_Pos) /* 0x00000800 */
#define TIM_BDTR_OSSR TIM_BDTR_OSSR_Msk /* Off-state selection for Run mode */
#define TIM_BDTR_BKE_Pos (12U)
#define TIM_BDTR_BKE_Msk (0x1U << TIM_BDTR_BKE_Pos) /* 0x00001000 */
#define TIM_BDTR_BKE TIM_BDTR_BKE_Msk /* Break enable */
#define TIM_BDTR_BKP_Pos (13U)
#define TIM_BDTR_BKP_Msk (0x1U << TIM_BDTR_BKP_Pos) /* 0x00002000 */
#define TIM_BDTR_BKP TIM_BDTR_BKP_Msk /* Break polarity */
#define TIM_BDTR_AOE_Pos (14U)
#define TIM_BDTR_AOE_Msk (0x1U << TIM_BDTR_AOE_Pos) /* 0x00004000 */
#define TIM_BDTR_AOE TIM_BDTR_AOE_Msk /* Automatic output enable */
#define TIM_BDTR_MOE_Pos (15U)
#define TIM_BDTR_MOE_Msk (0x1U << TIM_BDTR_MOE_Pos) /* 0x00008000 */
#define TIM_BDTR_MOE TIM_BDTR_MOE_Msk /* Main output enable */

/* RCC_CR */
#define RCC_CR_HSION_Pos (0U)
#define RCC_CR_HSION_Msk (0x1U << RCC_CR_HSION_Pos) /* 0x00000001 */
#define RCC_CR_HSION RCC_CR_HSION_Msk /* Internal High Speed clock enable */
#define RCC_CR_HSIRDY_Pos (1U)
#define RCC_CR_HSIRDY_Msk (0x1U << RCC_CR_HSIRDY_Pos) /* 0x00000002 */
#define RCC_CR_HSIRDY RCC_CR_HSIRDY_Msk /* Internal High Speed clock ready flag */
#define RCC_CR_HSITRIM_Pos (3U)
#define RCC_CR_HSITRIM_Msk (0x1fU << RCC_CR_HSITRIM_Pos) /* 0x000000F8 */
#define RCC_CR_HSITRIM RCC_CR_HSITRIM_Msk /* Internal High Speed clock trimming */
#define RCC_CR_HSITRIM_0 (0x1U << RCC_CR_HSITRIM_Pos) /* 0x00000008 */
#define RCC_CR_HSITRIM_1 (0x2U << RCC_CR_HSITRIM_Pos) /* 0x00000010 */
#define RCC_CR_HSITRIM_2 (0x4U << RCC_CR_HSITRIM_Pos) /* 0x00000020 */
#define RCC_CR_HSITRIM_3 (0x8U << RCC_CR_HSITRIM_Pos) /* 0x00000040 */
#define RCC_CR_HSITRIM_4 (0x10U << RCC_CR_HSITRIM_Pos) /* 0x00000080 */
#define RCC_CR_HSICAL_Pos (8U)
#define RCC_CR_HSICAL_Msk (0xffU << RCC_CR_HSICAL_Pos) /* 0x0000FF00 */
#define RCC_CR_HSICAL RCC_CR_HSICAL_Msk /* Internal High Speed clock Calibration */
#define RCC_CR_HSICAL_0 (0x1U << RCC_CR_HSICAL_Pos) /* 0x00000100 */
#define RCC_CR_HSICAL_1 (0x2U << RCC_CR_HSICAL_Pos) /* 0x00000200 */
#define RCC_CR_HSICAL_2 (0x4U << RCC_CR_HSICAL_Pos) /* 0x00000400 */
#define RCC_CR_HSICAL_3 (0x8U << RCC_CR_HSICAL_Pos) /* 0x00000800 */
#define RCC_CR_HSICAL_4 (0x10U << RCC_CR_HSICAL_Pos) /* 0x00001000 */
#define RCC_CR_HSICAL_5 (0x20U << RCC_CR_HSICAL_Pos) /* 0x00002000 */
#define RCC_CR_HSICAL_6 (0x40U << RCC_CR_HSICAL_Pos) /* 0x00004000 */
#define RCC_CR_HSICAL_7 (0x80U << RCC_CR_HSICAL_Pos) /* 0x00008000 */
#define RCC_CR_HSEON_Pos (16U)
#define RCC_CR_HSEON_Msk (0x1U << RCC_CR_HSEON_Pos) /* 0x00010000 */
#define RCC_CR_HSEON RCC_CR_HSEON_Msk /* External High Speed clock enable */
#define RCC_CR_HSERDY_Pos (17U)
#define RCC_CR_HSERDY_Msk (0x1U << RCC_CR_HSERDY_Pos) /* 0x00020000 */
#define RCC_CR_HSERDY RCC_CR_HSERDY_Msk /* External High Speed clock ready flag */
#define RCC_CR_HSEBYP_Pos (18U)
#define RCC_CR_HSEBYP_Msk (0x1U << RCC_CR_HSEBYP_Pos) /* 0x00040000 */
#define RCC_CR_HSEBYP RCC_CR_HSEBYP_Msk /* External High Speed clock Bypass */
#define RCC_CR_CSSON_Pos (19U)
#define RCC_CR_CSSON_Msk (0x1U << RCC_CR_CSSON_Pos) /* 0x00080000 */
#define RCC_CR_CSSON RCC_CR_CSSON_Msk /* Clock Security System enable */
#define RCC_CR_PLLON_Pos (24U)
#define RCC_CR_PLLON_Msk (0x1U << RCC_CR_PLLON_Pos) /* 0x01000000 */
#define RCC_CR_PLLON RCC_CR_PLLON_Msk /* PLL enable */
#define RCC_CR_PLLRDY_Pos (25U)
#define RCC_CR_PLLRDY_Msk (0x1U << RCC_CR_PLLRDY_Pos) /* 0x02000000 */
#define RCC_CR_PLLRDY RCC_CR_PLLRDY_Msk /* PLL clock ready flag */

/* RCC_CFGR */
#define RCC_CFGR_SW_Pos (0U)
#define RCC_CFGR_SW_Msk (0x3U << RCC_CFGR_SW_Pos) /* 0x00000003 */
#define RCC_CFGR_SW RCC_CFGR_SW_Msk /* System clock Switch */
#define RCC_CFGR_SW_0 (0x1U << RCC_CFGR_SW_Pos) /* 0x00000001 */
#define RCC_CFGR_SW_1 (0x2U << RCC_CFGR_SW_Pos) /* 0x00000002 */
#define RCC_CFGR_SWS_Pos (2U)
#define RCC_CFGR_SWS_Msk (0x3U << RCC_CFGR_SWS_Pos) /* 0x0000000C */
#define RCC_CFGR_SWS RCC_CFGR_SWS_Msk /* System Clock Switch Status */
#define RCC_CFGR_SWS_0 (0x1U << RCC_CFGR_SWS_Pos) /* 0x00000004 */
#define RCC_CFGR_SWS_1 (0x2U << RCC_CFGR_SWS_Pos) /* 0x00000008 */
#define RCC_CFGR_HPRE_Pos (4U)
#define RCC_CFGR_HPRE_Msk (0xfU << RCC_CFGR_HPRE_Pos) /* 0x000000F0 */
#define RCC_CFGR_HPRE RCC_CFGR_HPRE_Msk /* AHB prescaler */
#define RCC_CFGR_HPRE_0 (0x1U << RCC_CFGR_HPRE_Pos) /* 0x00000010 */
#define RCC_CFGR_HPRE_1 (0x2U << RCC_CFGR_HPRE_Pos) /* 0x00000020 */
#define RCC_CFGR_HPRE_2 (0x4U << RCC_CFGR_HPRE_Pos) /* 0x00000040 */
#define RCC_CFGR_HPRE_3 (0x8U << RCC_CFGR_HPRE_Pos) /* 0x00000080 */
#define RCC_CFGR_PPRE1_Pos (8U)
#define RCC_CFGR_PPRE1_Msk (0x7U << RCC_CFGR_PPRE1_Pos) /* 0x00000700 */
#define RCC_CFGR_PPRE1 RCC_CFGR_PPRE1_Msk /* APB Low speed prescaler (APB1) */
#define RCC_CFGR_PPRE1_0 (0x1U << RCC_CFGR_PPRE1_Pos) /* 0x00000100 */
#define RCC_CFGR_PPRE1_1 (0x2U << RCC_CFGR_PPRE1_Pos) /* 0x00000200 */
#define RCC_CFGR_PPRE1_2 (0x4U << RCC_CFGR_PPRE1_Pos) /* 0x00000400 */
#define RCC_CFGR_PPRE2_Pos (11U)
#define RCC_CFGR_PPRE2_Msk (0x7U << RCC_CFGR_PPRE2_Pos) /* 0x00003800 */
#define RCC_CFGR_PPRE2 RCC_CFGR_PPRE2_Msk /* APB High speed prescaler (APB2) */
#define RCC_CFGR_PPRE2_0 (0x1U << RCC_CFGR_PPRE2_Pos) /* 0x00000800 */
#define RCC_CFGR_PPRE2_1 (0x2U << RCC_CFGR_PPRE2_Pos) /* 0x00001000 */
#define RCC_CFGR_PPRE2_2 (0x4U << RCC_CFGR_PPRE2_Pos) /* 0x00002000 */
#define RCC_CFGR_ADCPRE_Pos (14U)
#define RCC_CFGR_ADCPRE_Msk (0x3U << RCC_CFGR_ADCPRE_Pos) /* 0x0000C000 */
#define RCC_CFGR_ADCPRE RCC_CFGR_ADCPRE_Msk /* ADC prescaler */
#define RCC_CFGR_ADCPRE_0 (0x1U << RCC_CFGR_ADCPRE_Pos) /* 0x00004000 */
#define RCC_CFGR_ADCPRE_1 (0x2U << RCC_CFGR_ADCPRE_Pos) /* 0x00008000 */
#define RCC_CFGR_PLLSRC_Pos (16U)
#define RCC_CFGR_PLLSRC_Msk (0x1U << RCC_CFGR_PLLSRC_Pos) /* 0x00010000 */
#define RCC_CFGR_PLLSRC RCC_CFGR_PLLSRC_Msk /* PLL entry clock source */
#define RCC_CFGR_PLLXTPRE_Pos (17U)
#define RCC_CFGR_PLLXTPRE_Msk (0x1U << RCC_CFGR_PLLXTPRE_Pos) /* 0x00020000 */
#define RCC_CFGR_PLLXTPRE RCC_CFGR_PLLXTPRE_Msk /* HSE divider for PLL entry */
#define RCC_CFGR_PLLMUL_Pos (18U)
#define RCC_CFGR_PLLMUL_Msk (0xfU << RCC_CFGR_PLLMUL_Pos) /* 0x003C0000 */
#define RCC_CFGR_PLLMUL RCC_CFGR_PLLMUL_Msk /* PLL Multiplication Factor */
#define RCC_CFGR_PLLMUL_0 (0x1U << RCC_CFGR_PLLMUL_Pos) /* 0x00040000 */
#define RCC_CFGR_PLLMUL_1 (0x2U << RCC_CFGR_PLLMUL_Pos) /* 0x00080000 */
#define RCC_CFGR_PLLMUL_2 (0x4U << RCC_CFGR_PLLMUL_Pos) /* 0x00100000 */
#define RCC_CFGR_PLLMUL_3 (0x8U << RCC_CFGR_PLLMUL_Pos) /* 0x00200000 */
#define RCC_CFGR_OTGFSPRE_Pos (22U)
#define RCC_CFGR_OTGFSPRE_Msk (0x1U << RCC_CFGR_OTGFSPRE_Pos) /* 0x00400000 */
#define RCC_CFGR_OTGFSPRE RCC_CFGR_OTGFSPRE_Msk /* USB OTG FS prescaler */
#define RCC_CFGR_MCO_Pos (24U)
#define RCC_CFGR_MCO_Msk (0x7U << RCC_CFGR_MCO_Pos) /* 0x07000000 */
#define RCC_CFGR_MCO RCC_CFGR_MCO_Msk /* Microcontroller clock output */
#define RCC_CFGR_MCO_0 (0x1U << RCC_CFGR_MCO_Pos) /* 0x01000000 */
#define RCC_CFGR_MCO_1 (0x2U << RCC_CFGR_MCO_Pos) /* 0x02000000 */
#define RCC_CFGR_MCO_2 (0x4U << RCC_CFGR_MCO_Pos) /* 0x04000000 */

/* RCC_CIR */
#define RCC_CIR_LSIRDYF_Pos (0U)
#define RCC_CIR_LSIRDYF_Msk (0x1U << RCC_CIR_LSIRDYF_Pos) /* 0x00000001 */
#define RCC_CIR_LSIRDYF RCC_CIR_LSIRDYF_Msk /* LSI Ready Interrupt flag */
#define RCC_CIR_LSERDYF_Pos (1U)
#define RCC_CIR_LSERDYF_Msk (0x1U << RCC_CIR_LSERDYF_Pos) /* 0x00000002 */
#define RCC_CIR_LSERDYF RCC_CIR_LSERDYF_Msk /* LSE Ready Interrupt flag */
#define RCC_CIR_HSIRDYF_Pos (2U)
#define RCC_CIR_HSIRDYF_Msk (0x1U << RCC_CIR_HSIRDYF_Pos) /* 0x00000004 */
#define RCC_CIR_HSIRDYF RCC_CIR_HSIRDYF_Msk /* HSI Ready Interrupt flag */
#define RCC_CIR_HSERDYF_Pos (3U)
#define RCC_CIR_HSERDYF_Msk (0x1U << RCC_CIR_HSERDYF_Pos) /* 0x00000008 */
#define RCC_CIR_HSERDYF RCC_CIR_HSERDYF_Msk /* HSE Ready Interrupt flag */
#define RCC_CIR_PLLRDYF_Pos (4U)
#define RCC_CIR_PLLRDYF_Msk (0x1U << RCC_CIR_PLLRDYF_Pos) /* 0x00000010 */
#define RCC_CIR_PLLRDYF RCC_CIR_PLLRDYF_Msk /* PLL Ready Interrupt flag */
#define RCC_CIR_CSSF_Pos (7U)
#define RCC_CIR_CSSF_Msk (0x1U << RCC_CIR_CSSF_Pos) /* 0x00000080 */
#define RCC_CIR_CSSF RCC_CIR_CSSF_Msk /* Clock Security System Interrupt flag */
#define RCC_CIR_LSIRDYIE_Pos (8U)
#define RCC_CIR_LSIRDYIE_Msk (0x1U << RCC_CIR_LSIRDYIE_Pos) /* 0x00000100 */
#define RCC_CIR_LSIRDYIE RCC_CIR_LSIRDYIE_Msk /* LSI Ready Interrupt Enable */
#define RCC_CIR_LSERDYIE_Pos (9U)
#define RCC_CIR_LSERDYIE_Msk (0x1U << RCC_CIR_LSERDYIE_Pos) /* 0x00000200 */
#define RCC_CIR_LSERDYIE RCC_CIR_LSERDYIE_Msk /* LSE Ready Interrupt Enable */
#define RCC_CIR_HSIRDYIE_Pos (10U)
#define RCC_CIR_HSIRDYIE_Msk (0x1U << RCC_CIR_HSIRDYIE_Pos) /* 0x00000400 */
#define RCC_CIR_HSIRDYIE RCC_CIR_HSIRDYIE_Msk /* HSI Ready Interrupt Enable */
#define RCC_CIR_HSERDYIE_Pos (11U)
#define RCC_CIR_HSERDYIE_Msk (0x1U << RCC_CIR_HSERDYIE_Pos) /* 0x00000800 */
#define RCC_CIR_HSERDYIE RCC_CIR_HSERDYIE_Msk /* HSE Ready Interrupt Enable */
#define RCC_CIR_PLLRDYIE_Pos (12U)
#define RCC_CIR_PLLRDYIE_Msk (0x1U << RCC_CIR_PLLRDYIE_Pos) /* 0x00001000 */
#define RCC_CIR_PLLRDYIE RCC_CIR_PLLRDYIE_Msk /* PLL Ready Interrupt Enable */
#define RCC_CIR_LSIRDYC_Pos (16U)
#define RCC_CIR_LSIRDYC_Msk (0x1U << RCC_CIR_LSIRDYC_Pos) /* 0x00010000 */
#define RCC_CIR_LSIRDYC RCC_CIR_LSIRDYC_Msk /* LSI Ready Interrupt Clear */
#define RCC_CIR_LSERDYC_Pos (17U)
#define RCC_CIR_LSERDYC_Msk (0x1U << RCC_CIR_LSERDYC_Pos) /* 0x00020000 */
#define RCC_CIR_LSERDYC RCC_CIR_LSERDYC_Msk /* LSE Ready Interrupt Clear */
#define RCC_CIR_HSIRDYC_Pos (18U)
#define RCC_CIR_HSIRDYC_Msk (0x1U << RCC_CIR_HSIRDYC_Pos) /* 0x00040000 */
#define RCC_CIR_HSIRDYC RCC_CIR_HSIRDYC_Msk /* HSI Ready Interrupt Clear */
#define RCC_CIR_HSERDYC_Pos (19U)
#define RCC_CIR_HSERDYC_Msk (0x1U << RCC_CIR_HSERDYC_Pos) /* 0x00080000 */
#define RCC_CIR_HSERDYC RCC_CIR_HSERDYC_Msk /* HSE Ready Interrupt Clear */
#define RCC_CIR_PLLRDYC_Pos (20U)
#define RCC_CIR_PLLRDYC_Msk (0x1U << RCC_CIR_PLLRDYC_Pos) /* 0x00100000 */
#define RCC_CIR_PLLRDYC RCC_CIR_PLLRDYC_Msk /* PLL Ready Interrupt Clear */
#define RCC_CIR_CSSC_Pos (23U)
#define RCC_CIR_CSSC_Msk (0x1U << RCC_CIR_CSSC_Pos) /* 0x00800000 */
#define RCC_CIR_CSSC RCC_CIR_CSSC_Msk /* Clock security system interrupt clear */

/* RCC_APB2ENR */
#define RCC_APB2ENR_AFIOEN_Pos (0U)
#define RCC_APB2ENR_AFIOEN_Msk (0x1U << RCC_APB2ENR_AFIOEN_Pos) /* 0x00000001 */
#define RCC_APB2ENR_AFIOEN RCC_APB2ENR_AFIOEN_Msk /* Alternate function I/O clock enable */
#define RCC_APB2ENR_IOPAEN_Pos (2U)
#define RCC_APB2ENR_IOPAEN_Msk (0x1U << RCC_APB2ENR_IOPAEN_Pos) /* 0x00000004 */
#define RCC_APB2ENR_IOPAEN RCC_APB2ENR_IOPAEN_Msk /* I/O port A clock enable */
#define RCC_APB2ENR_IOPBEN_Pos (3U)
#define RCC_APB2ENR_IOPBEN_Msk (0x1U << RCC_APB2ENR_IOPBEN_Pos) /* 0x00000008 */
#define RCC_APB2ENR_IOPBEN RCC_APB2ENR_IOPBEN_Msk /* I/O port B clock enable */
#define RCC_APB2ENR_IOPCEN_Pos (4U)
#define RCC_APB2ENR_IOPCEN_Msk (0x1U << RCC_APB2ENR_IOPCEN_Pos) /* 0x00000010 */
#define RCC_APB2ENR_IOPCEN RCC_APB2ENR_IOPCEN_Msk /* I/O port C clock enable */
#define RCC_APB2ENR_IOPDEN_Pos (5U)
#define RCC_APB2ENR_IOPDEN_Msk (0x1U << RCC_APB2ENR_IOPDEN_Pos) /* 0x00000020 */
#define RCC_APB2ENR_IOPDEN RCC_APB2ENR_IOPDEN_Msk /* I/O port D clock enable */
#define RCC_APB2ENR_IOPEEN_Pos (6U)
#define RCC_APB2ENR_IOPEEN_Msk (0x1U << RCC_APB2ENR_IOPEEN_Pos) /* 0x00000040 */
#define RCC_APB2ENR_IOPEEN RCC_APB2ENR_IOPEEN_Msk /* I/O port E clock enable */
#define RCC_APB2ENR_IOPFEN_Pos (7U)
#define RCC_APB2ENR_IOPFEN_Msk (0x1U << RCC_APB2ENR_IOPFEN_Pos) /* 0x00000080 */
#define RCC_APB2ENR_IOPFEN RCC_APB2ENR_IOPFEN_Msk /* I/O port F clock enable */
#define RCC_APB2ENR_IOPGEN_Pos (8U)
#define RCC_APB2ENR_IOPGEN_Msk (0x1U << RCC_APB2ENR_IOPGEN_Pos) /* 0x00000100 */
#define RCC_APB2ENR_IOPGEN RCC_APB2ENR_IOPGEN_Msk /* I/O port G clock enable */
#define RCC_APB2ENR_ADC1EN_Pos (9U)
#define RCC_APB2ENR_ADC1EN_Msk (0x1U << RCC_APB2ENR_ADC1EN_Pos) /* 0x00000200 */
#define RCC_APB2ENR_ADC1EN RCC_APB2ENR_ADC1EN_Msk /* ADC 1 interface clock enable */
#define RCC_APB2ENR_ADC2EN_Pos (10U)
#define RCC_APB2ENR_ADC2EN_Msk (0x1U << RCC_APB2ENR_ADC2EN_Pos) /* 0x00000400 */
#define RCC_APB2ENR_ADC2EN RCC_APB2ENR_ADC2EN_Msk /* ADC 2 interface clock enable */
#define RCC_APB2ENR_TIM1EN_Pos (11U)
#define RCC_APB2ENR_TIM1EN_Msk (0x1U << RCC_APB2ENR_TIM1EN_Pos) /* 0x00000800 */
#define RCC_APB2ENR_TIM1EN RCC_APB2ENR_TIM1EN_Msk /* TIM1 Timer clock enable */
#define RCC_APB2ENR_SPI1EN_Pos (12U)
#define RCC_APB2ENR_SPI1EN_Msk (0x1U << RCC_APB2ENR_SPI1EN_Pos) /* 0x00001000 */
#define RCC_APB2ENR_SPI1EN RCC_APB2ENR_SPI1EN_Msk /* SPI 1 clock enable */
#define RCC_APB2ENR_TIM8EN_Pos (13U)
#define RCC_APB2ENR_TIM8EN_Msk (0x1U << RCC_APB2ENR_TIM8EN_Pos) /* 0x00002000 */
#define RCC_APB2ENR_TIM8EN RCC_APB2ENR_TIM8EN_Msk /* TIM8 Timer clock enable */
#define RCC_APB2ENR_USART1EN_Pos (14U)
#define RCC_APB2ENR_USART1EN_Msk (0x1U << RCC_APB2ENR_USART1EN_Pos) /* 0x00004000 */
#define RCC_APB2ENR_USART1EN RCC_APB2ENR_USART1EN_Msk /* USART1 clock enable */
#define RCC_APB2ENR_ADC3EN_Pos (15U)
#define RCC_APB2ENR_ADC3EN_Msk (0x1U << RCC_APB2ENR_ADC3EN_Pos) /* 0x00008000 */
#define RCC_APB2ENR_ADC3EN RCC_APB2ENR_ADC3EN_Msk /* ADC3 interface clock enable */
#define RCC_APB2ENR_TIM9EN_Pos (19U)
#define RCC_APB2ENR_TIM9EN_Msk (0x1U << RCC_APB2ENR_TIM9EN_Pos) /* 0x00080000 */
#define RCC_APB2ENR_TIM9EN RCC_APB2ENR_TIM9EN_Msk /* TIM9 Timer clock enable */
#define RCC_APB2ENR_TIM10EN_Pos (20U)
#define RCC_APB2ENR_TIM10EN_Msk (0x1U << RCC_APB2ENR_TIM10EN_Pos) /* 0x00100000 */
#define RCC_APB2ENR_TIM10EN RCC_APB2ENR_TIM10EN_Msk /* TIM10 Timer clock enable */
#define RCC_APB2ENR_TIM11EN_Pos (21U)
#define RCC_APB2ENR_TIM11EN_Msk (0x1U << RCC_APB2ENR_TIM11EN_Pos) /* 0x00200000 */
#define RCC_APB2ENR_TIM11EN RCC_APB2ENR_TIM11EN_Msk /* TIM11 Timer clock enable */

/* RCC_APB1ENR */
#define RCC_APB1ENR_TIM2EN_Pos (0U)
#define RCC_APB1ENR_TIM2EN_Msk (0x1U << RCC_APB1ENR_TIM2EN_Pos) /* 0x00000001 */
#define RCC_APB1ENR_TIM2EN RCC_APB1ENR_TIM2EN_Msk /* Timer 2 clock enable */
#define RCC_APB1ENR_TIM3EN_Pos (1U)
#define RCC_APB1ENR_TIM3EN_Msk (0x1U << RCC_APB1ENR_TIM3EN_Pos) /* 0x00000002 */
#define RCC_APB1ENR_TIM3EN RCC_APB1ENR_TIM3EN_Msk /* Timer 3 clock enable */
#define RCC_APB1ENR_TIM4EN_Pos (2U)
#define RCC_APB1ENR_TIM4EN_Msk (0x1U << RCC_APB1ENR_TIM4EN_Pos) /* 0x00000004 */
#define RCC_APB1ENR_TIM4EN RCC_APB1ENR_TIM4EN_Msk /* Timer 4 clock enable */
#define RCC_APB1ENR_TIM5EN_Pos (3U)
#define RCC_APB1ENR_TIM5EN_Msk (0x1U << RCC_APB1ENR_TIM5EN_Pos) /* 0x00000008 */
#define RCC_APB1ENR_TIM5EN RCC_APB1ENR_TIM5EN_Msk /* Timer 5 clock enable */
#define RCC_APB1ENR_TIM6EN_Pos (4U)
#define RCC_APB1ENR_TIM6EN_Msk (0x1U << RCC_APB1ENR_TIM6EN_Pos) /* 0x00000010 */
#define RCC_APB1ENR_TIM6EN RCC_APB1ENR_TIM6EN_Msk /* Timer 6 clock enable */
#define RCC_APB1ENR_TIM7EN_Pos (5U)
#define RCC_APB1ENR_TIM7EN_Msk (0x1U << RCC_APB1ENR_TIM7EN_Pos) /* 0x00000020 */
#define RCC_APB1ENR_TIM7EN RCC_APB1ENR_TIM7EN_Msk /* Timer 7 clock enable */
#define RCC_APB1ENR_TIM12EN_Pos (6U)
#define RCC_APB1ENR_TIM12EN_Msk (0x1U << RCC_APB1ENR_TIM12EN_Pos) /* 0x00000040 */
#define RCC_APB1ENR_TIM12EN RCC_APB1ENR_TIM12EN_Msk /* Timer 12 clock enable */
#define RCC_APB1ENR_TIM13EN_Pos (7U)
#define RCC_APB1ENR_TIM13EN_Msk (0x1U << RCC_APB1ENR_TIM13EN_Pos) /* 0x00000080 */
#define RCC_APB1ENR_TIM13EN RCC_APB1ENR_TIM13EN_Msk /* Timer 13 clock enable */
#define RCC_APB1ENR_TIM14EN_Pos (8U)
#define RCC_APB1ENR_TIM14EN_Msk (0x1U << RCC_APB1ENR_TIM14EN_Pos) /* 0x00000100 */
#define RCC_APB1ENR_TIM14EN RCC_APB1ENR_TIM14EN_Msk /* Timer 14 clock enable */
#define RCC_APB1ENR_WWDGEN_Pos (11U)
#define RCC_APB1ENR_WWDGEN_Msk (0x1U << RCC_APB1ENR_WWDGEN_Pos) /* 0x00000800 */
#define RCC_APB1ENR_WWDGEN RCC_APB1ENR_WWDGEN_Msk /* Window watchdog clock enable */
#define RCC_APB1ENR_SPI2EN_Pos (14U)
#define RCC_APB1ENR_SPI2EN_Msk (0x1U << RCC_APB1ENR_SPI2EN_Pos) /* 0x00004000 */
#define RCC_APB1ENR_SPI2EN RCC_APB1ENR_SPI2EN_Msk /* SPI 2 clock enable */
#define RCC_APB1ENR_SPI3EN_Pos (15U)
#define RCC_APB1ENR_SPI3EN_Msk (0x1U << RCC_APB1ENR_SPI3EN_Pos) /* 0x00008000 */
#define RCC_APB1ENR_SPI3EN RCC_APB1ENR_SPI3EN_Msk /* SPI 3 clock enable */
#define RCC_APB1ENR_USART2EN_Pos (17U)
#define RCC_APB1ENR_USART2EN_Msk (0x1U << RCC_APB1ENR_USART2EN_Pos) /* 0x00020000 */
#define RCC_APB1ENR_USART2EN RCC_APB1ENR_USART2EN_Msk /* USART 2 clock enable */
#define RCC_APB1ENR_USART3EN_Pos (18U)
#define RCC_APB1ENR_USART3EN_Msk (0x1U << RCC_APB1ENR_USART3EN_Pos) /* 0x00040000 */
#define RCC_APB1ENR_USART3EN RCC_APB1ENR_USART3EN_Msk /* USART 3 clock enable */
#define RCC_APB1ENR_UART4EN_Pos (19U)
#define RCC_APB1ENR_UART4EN_Msk (0x1U << RCC_APB1ENR_UART4EN_Pos) /* 0x00080000 */
#define RCC_APB1ENR_UART4EN RCC_APB1ENR_UART4EN_Msk /* UART 4 clock enable */
#define RCC_APB1ENR_UART5EN_Pos (20U)
#define RCC_APB1ENR_UART5EN_Msk (0x1U << RCC_APB1ENR_UART5EN_Pos) /* 0x00100000 */
#define RCC_APB1ENR_UART5EN RCC_APB1ENR_UART5EN_Msk /* UART 5 clock enable */
#define RCC_APB1ENR_I2C1EN_Pos (21U)
#define RCC_APB1ENR_I2C1EN_Msk (0x1U << RCC_APB1ENR_I2C1EN_Pos) /* 0x00200000 */
#define RCC_APB1ENR_I2C1EN RCC_APB1ENR_I2C1EN_Msk /* I2C 1 clock enable */
#define RCC_APB1ENR_I2C2EN_Pos (22U)
#define RCC_APB1ENR_I2C2EN_Msk (0x1U << RCC_APB1ENR_I2C2EN_Pos) /* 0x00400000 */
#define RCC_APB1ENR_I2C2EN RCC_APB1ENR_I2C2EN_Msk /* I2C 2 clock enable */
#define RCC_APB1ENR_USBEN_Pos (23U)
#define RCC_APB1ENR_USBEN_Msk (0x1U << RCC_APB1ENR_USBEN_Pos) /* 0x00800000 */
#define RCC_APB1ENR_USBEN RCC_APB1ENR_USBEN_Msk /* USB clock enable */
#define RCC_APB1ENR_CANEN_Pos (25U)
#define RCC_APB1ENR_CANEN_Msk (0x1U << RCC_APB1ENR_CANEN_Pos) /* 0x02000000 */
#define RCC_APB1ENR_CANEN RCC_APB1ENR_CANEN_Msk /* CAN clock enable */
#define RCC_APB1ENR_BKPEN_Pos (27U)
#define RCC_APB1ENR_BKPEN_Msk (0x1U << RCC_APB1ENR_BKPEN_Pos) /* 0x08000000 */
#define RCC_APB1ENR_BKPEN RCC_APB1ENR_BKPEN_Msk /* Backup interface clock enable */
#define RCC_APB1ENR_PWREN_Pos (28U)
#define RCC_APB1ENR_PWREN_Msk (0x1U << RCC_APB1ENR_PWREN_Pos) /* 0x10000000 */
#define RCC_APB1ENR_PWREN RCC_APB1ENR_PWREN_Msk /* Power interface clock enable */
#define RCC_APB1ENR_DACEN_Pos (29U)
#define RCC_APB1ENR_DACEN_Msk (0x1U << RCC_APB1ENR_DACEN_Pos) /* 0x20000000 */
#define RCC_APB1ENR_DACEN RCC_APB1ENR_DACEN_Msk /* DAC interface clock enable */

/* RCC_CSR */
#define RCC_CSR_LSION_Pos (0U)
#define RCC_CSR_LSION_Msk (0x1U << RCC_CSR_LSION_Pos) /* 0x00000001 */
#define RCC_CSR_LSION RCC_CSR_LSION_Msk /* Internal low speed oscillator enable */
#define RCC_CSR_LSIRDY_Pos (1U)
#define RCC_CSR_LSIRDY_Msk (0x1U << RCC_CSR_LSIRDY_Pos) /* 0x00000002 */
#define RCC_CSR_LSIRDY RCC_CSR_LSIRDY_Msk /* Internal low speed oscillator ready */
#define RCC_CSR_RMVF_Pos (24U)
#define RCC_CSR_RMVF_Msk (0x1U << RCC_CSR_RMVF_Pos) /* 0x01000000 */
#define RCC_CSR_RMVF RCC_CSR_RMVF_Msk /* Remove reset flag */
#define RCC_CSR_PINRSTF_Pos (26U)
#define RCC_CSR_PINRSTF_Msk (0x1U << RCC_CSR_PINRSTF_Pos) /* 0x04000000 */
#define RCC_CSR_PINRSTF RCC_CSR_PINRSTF_Msk /* PIN reset flag */
#define RCC_CSR_PORRSTF_Pos (27U)
#define RCC_CSR_PORRSTF_Msk (0x1U << RCC_CSR_PORRSTF_Pos) /* 0x08000000 */
#define RCC_CSR_PORRSTF RCC_CSR_PORRSTF_Msk /* POR/PDR reset flag */
#define RCC_CSR_SFTRSTF_Pos (28U)
#define RCC_CSR_SFTRSTF_Msk (0x1U << RCC_CSR_SFTRSTF_Pos) /* 0x10000000 */
#define RCC_CSR_SFTRSTF RCC_CSR_SFTRSTF_Msk /* Software reset flag */
#define RCC_CSR_IWDGRSTF_Pos (29U)
#define RCC_CSR_IWDGRSTF_Msk (0x1U << RCC_CSR_IWDGRSTF_Pos) /* 0x20000000 */
#define RCC_CSR_IWDGRSTF RCC_CSR_IWDGRSTF_Msk /* Independent watchdog reset flag */
#define RCC_CSR_WWDGRSTF_Pos (30U)
#define RCC_CSR_WWDGRSTF_Msk (0x1U << RCC_CSR_WWDGRSTF_Pos) /* 0x40000000 */
#define RCC_CSR_WWDGRSTF RCC_CSR_WWDGRSTF_Msk /* Window watchdog reset flag */
#define RCC_CSR_LPWRRSTF_Pos (31U)
#define RCC_CSR_LPWRRSTF_Msk (0x1U << RCC_CSR_LPWRRSTF_Pos) /* 0x80000000 */
#define RCC_CSR_LPWRRSTF RCC_CSR_LPWRRSTF_Msk /* Low-power reset flag */

/* GPIO_CRL */
#define GPIO_CRL_MODE0_Pos (0U)
#define GPIO_CRL_MODE0_Msk (0x3U << GPIO_CRL_MODE0_Pos) /* 0x00000003 */
#define GPIO_CRL_MODE0 GPIO_CRL_MODE0_Msk /* Port n.0 mode bits */
#define GPIO_CRL_MODE0_0 (0x1U << GPIO_CRL_MODE0_Pos) /* 0x00000001 */
#define GPIO_CRL_MODE0_1 (0x2U << GPIO_CRL_MODE0_Pos) /* 0x00000002 */
#define GPIO_CRL_CNF0_Pos (2U)
#define GPIO_CRL_CNF0_Msk (0x3U << GPIO_CRL_CNF0_Pos) /* 0x0000000C */
#define GPIO_CRL_CNF0 GPIO_CRL_CNF0_Msk /* Port n.0 configuration bits */
#define GPIO_CRL_CNF0_0 (0x1U << GPIO_CRL_CNF0_Pos) /* 0x00000004 */
#define GPIO_CRL_CNF0_1 (0x2U << GPIO_CRL_CNF0_Pos) /* 0x00000008 */
#define GPIO_CRL_MODE1_Pos (4U)
#define GPIO_CRL_MODE1_Msk (0x3U << GPIO_CRL_MODE1_Pos) /* 0x00000030 */
#define GPIO_CRL_MODE1 GPIO_CRL_MODE1_Msk /* Port n.1 mode bits */
#define GPIO_CRL_MODE1_0 (0x1U << GPIO_CRL_MODE1_Pos) /* 0x00000010 */
#define GPIO_CRL_MODE1_1 (0x2U << GPIO_CRL_MODE1_Pos) /* 0x00000020 */
#define GPIO_CRL_CNF1_Pos (6U)
#define GPIO_CRL_CNF1_Msk (0x3U << GPIO_CRL_CNF1_Pos) /* 0x000000C0 */
#define GPIO_CRL_CNF1 GPIO_CRL_CNF1_Msk /* Port n.1 configuration bits */
#define GPIO_CRL_CNF1_0 (0x1U << GPIO_CRL_CNF1_Pos) /* 0x00000040 */
#define GPIO_CRL_CNF1_1 (0x2U << GPIO_CRL_CNF1_Pos) /* 0x00000080 */
#define GPIO_CRL_MODE2_Pos (8U)
#define GPIO_CRL_MODE2_Msk (0x3U << GPIO_CRL_MODE2_Pos) /* 0x00000300 */
#define GPIO_CRL_MODE2 GPIO_CRL_MODE2_Msk /* Port n.2 mode bits */
#define GPIO_CRL_MODE2_0 (0x1U << GPIO_CRL_MODE2_Pos) /* 0x00000100 */
#define GPIO_CRL_MODE2_1 (0x2U << GPIO_CRL_MODE2_Pos) /* 0x00000200 */
#define GPIO_CRL_CNF2_Pos (10U)
#define GPIO_CRL_CNF2_Msk (0x3U << GPIO_CRL_CNF2_Pos) /* 0x00000C00 */
#define GPIO_CRL_CNF2 GPIO_CRL_CNF2_Msk /* Port n.2 configuration bits */
#define GPIO_CRL_CNF2_0 (0x1U << GPIO_CRL_CNF2_Pos) /* 0x00000400 */
#define GPIO_CRL_CNF2_1 (0x2U << GPIO_CRL_CNF2_Pos) /* 0x00000800 */
#define GPIO_CRL_MODE3_Pos (12U)
#define GPIO_CRL_MODE3_Msk (0x3U << GPIO_CRL_MODE3_Pos) /* 0x00003000 */
#define GPIO_CRL_MODE3 GPIO_CRL_MODE3_Msk /* Port n.3 mode bits */
#define GPIO_CRL_MODE3_0 (0x1U << GPIO_CRL_MODE3_Pos) /* 0x00001000 */
#define GPIO_CRL_MODE3_1 (0x2U << GPIO_CRL_MODE3_Pos) /* 0x00002000 */
#define GPIO_CRL_CNF3_Pos (14U)
#define GPIO_CRL_CNF3_Msk (0x3U << GPIO_CRL_CNF3_Pos) /* 0x0000C000 */
#define GPIO_CRL_CNF3 GPIO_CRL_CNF3_Msk /* Port n.3 configuration bits */
#define GPIO_CRL_CNF3_0 (0x1U << GPIO_CRL_CNF3_Pos) /* 0x00004000 */
#define GPIO_CRL_CNF3_1 (0x2U << GPIO_CRL_CNF3_Pos) /* 0x00008000 */
#define GPIO_CRL_MODE4_Pos (16U)
#define GPIO_CRL_MODE4_Msk (0x3U << GPIO_CRL_MODE4_Pos) /* 0x00030000 */
#define GPIO_CRL_MODE4 GPIO_CRL_MODE4_Msk /* Port n.4 mode bits */
#define GPIO_CRL_MODE4_0 (0x1U << GPIO_CRL_MODE4_Pos) /* 0x00010000 */
#define GPIO_CRL_MODE4_1 (0x2U << GPIO_CRL_MODE4_Pos) /* 0x00020000 */
#define GPIO_CRL_CNF4_Pos (18U)
#define GPIO_CRL_CNF4_Msk (0x3U << GPIO_CRL_CNF4_Pos) /* 0x000C0000 */
#define GPIO_CRL_CNF4 GPIO_CRL_CNF4_Msk /* Port n.4 configuration bits */
#define GPIO_CRL_CNF4_0 (0x1U << GPIO_CRL_CNF4_Pos) /* 0x00040000 */
#define GPIO_CRL_CNF4_1 (0x2U << GPIO_CRL_CNF4_Pos) /* 0x00080000 */
#define GPIO_CRL_MODE5_Pos (20U)
#define GPIO_CRL_MODE5_Msk (0x3U << GPIO_CRL_MODE5_Pos) /* 0x00300000 */
#define GPIO_CRL_MODE5 GPIO_CRL_MODE5_Msk /* Port n.5 mode bits */
#define GPIO_CRL_MODE5_0 (0x1U << GPIO_CRL_MODE5_Pos) /* 0x00100000 */
#define GPIO_CRL_MODE5_1 (0x2U << GPIO_CRL_MODE5_Pos) /* 0x00200000 */
#define GPIO_CRL_CNF5_Pos (22U)
#define GPIO_CRL_CNF5_Msk (0x3U << GPIO_CRL_CNF5_Pos) /* 0x00C00000 */
#define GPIO_CRL_CNF5 GPIO_CRL_CNF5_Msk /* Port n.5 configuration bits */
#define GPIO_CRL_CNF5_0 (0x1U << GPIO_CRL_CNF5_Pos) /* 0x00400000 */
#define GPIO_CRL_CNF5_1 (0x2U << GPIO_CRL_CNF5_Pos) /* 0x00800000 */
#define GPIO_CRL_MODE6_Pos (24U)
#define GPIO_CRL_MODE6_Msk (0x3U << GPIO_CRL_MODE6_Pos) /* 0x03000000 */
#define GPIO_CRL_MODE6 GPIO_CRL_MODE6_Msk /* Port n.6 mode bits */
#define GPIO_CRL_MODE6_0 (0x1U << GPIO_CRL_MODE6_Pos) /* 0x01000000 */
#define GPIO_CRL_MODE6_1 (0x2U << GPIO_CRL_MODE6_Pos) /* 0x02000000 */
#define GPIO_CRL_CNF6_Pos (26U)
#define GPIO_CRL_CNF6_Msk (0x3U << GPIO_CRL_CNF6_Pos) /* 0x0C000000 */
#define GPIO_CRL_CNF6 GPIO_CRL_CNF6_Msk /* Port n.6 configuration bits */
#define GPIO_CRL_CNF6_0 (0x1U << GPIO_CRL_CNF6_Pos) /* 0x04000000 */
#define GPIO_CRL_CNF6_1 (0x2U << GPIO_CRL_CNF6_Pos) /* 0x08000000 */
#define GPIO_CRL_MODE7_Pos (28U)
#define GPIO_CRL_MODE7_Msk (0x3U << GPIO_CRL_MODE7_Pos) /* 0x30000000 */
#define GPIO_CRL_MODE7 GPIO_CRL_MODE7_Msk /* Port n.7 mode bits */
#define GPIO_CRL_MODE7_0 (0x1U << GPIO_CRL_MODE7_Pos) /* 0x10000000 */
#define GPIO_CRL_MODE7_1 (0x2U << GPIO_CRL_MODE7_Pos) /* 0x20000000 */
#define GPIO_CRL_CNF7_Pos (30U)
#define GPIO_CRL_CNF7_Msk (0x3U << GPIO_CRL_CNF7_Pos) /* 0xC0000000 */
#define GPIO_CRL_CNF7 GPIO_CRL_CNF7_Msk /* Port n.7 configuration bits */
#define GPIO_CRL_CNF7_0 (0x1U << GPIO_CRL_CNF7_Pos) /* 0x40000000 */
#define GPIO_CRL_CNF7_1 (0x2U << GPIO_CRL_CNF7_Pos) /* 0x80000000 */

/* GPIO_CRH */
#define GPIO_CRH_MODE8_Pos (0U)
#define GPIO_CRH_MODE8_Msk (0x3U << GPIO_CRH_MODE8_Pos) /* 0x00000003 */
#define GPIO_CRH_MODE8 GPIO_CRH_MODE8_Msk /* Port n.8 mode bits */
#define GPIO_CRH_MODE8_0 (0x1U << GPIO_CRH_MODE8_Pos) /* 0x00000001 */
#define GPIO_CRH_MODE8_1 (0x2U << GPIO_CRH_MODE8_Pos) /* 0x00000002 */
#define GPIO_CRH_CNF8_Pos (2U)
#define GPIO_CRH_CNF8_Msk (0x3U << GPIO_CRH_CNF8_Pos) /* 0x0000000C */
#define GPIO_CRH_CNF8 GPIO_CRH_CNF8_Msk /* Port n.8 configuration bits */
#define GPIO_CRH_CNF8_0 (0x1U << GPIO_CRH_CNF8_Pos) /* 0x00000004 */
#define GPIO_CRH_CNF8_1 (0x2U << GPIO_CRH_CNF8_Pos) /* 0x00000008 */
#define GPIO_CRH_MODE9_Pos (4U)
#define GPIO_CRH_MODE9_Msk (0x3U << GPIO_CRH_MODE9_Pos) /* 0x00000030 */
#define GPIO_CRH_MODE9 GPIO_CRH_MODE9_Msk /* Port n.9 mode bits */
#define GPIO_CRH_MODE9_0 (0x1U << GPIO_CRH_MODE9_Pos) /* 0x00000010 */
#define GPIO_CRH_MODE9_1 (0x2U << GPIO_CRH_MODE9_Pos) /* 0x00000020 */
#define GPIO_CRH_CNF9_Pos (6U)
#define GPIO_CRH_CNF9_Msk (0x3U << GPIO_CRH_CNF9_Pos) /* 0x000000C0 */
#define GPIO_CRH_CNF9 GPIO_CRH_CNF9_Msk /* Port n.9 configuration bits */
#define GPIO_CRH_CNF9_0 (0x1U << GPIO_CRH_CNF9_Pos) /* 0x00000040 */
#define GPIO_CRH_CNF9_1 (0x2U << GPIO_CRH_CNF9_Pos) /* 0x00000080 */
#define GPIO_CRH_MODE10_Pos (8U)
#define GPIO_CRH_MODE10_Msk (0x3U << GPIO_CRH_MODE10_Pos) /* 0x00000300 */
#define GPIO_CRH_MODE10 GPIO_CRH_MODE10_Msk /* Port n.10 mode bits */
#define GPIO_CRH_MODE10_0 (0x1U << GPIO_CRH_MODE10_Pos) /* 0x00000100 */
#define GPIO_CRH_MODE10_1 (0x2U << GPIO_CRH_MODE10_Pos) /* 0x00000200 */
#define GPIO_CRH_CNF10_Pos (10U)
#define GPIO_CRH_CNF10_Msk (0x3U << GPIO_CRH_CNF10_Pos) /* 0x00000C00 */
#define GPIO_CRH_CNF10 GPIO_CRH_CNF10_Msk /* Port n.10 configuration bits */
#define GPIO_CRH_CNF10_0 (0x1U << GPIO_CRH_CNF10_Pos) /* 0x00000400 */
#define GPIO_CRH_CNF10_1 (0x2U << GPIO_CRH_CNF10_Pos) /* 0x00000800 */
#define GPIO_CRH_MODE11_Pos (12U)
#define GPIO_CRH_MODE11_Msk (0x3U << GPIO_CRH_MODE11_Pos) /* 0x00003000 */
#define GPIO_CRH_MODE11 GPIO_CRH_MODE11_Msk /* Port n.11 mode bits */
#define GPIO_CRH_MODE11_0 (0x1U << GPIO_CRH_MODE11_Pos) /* 0x00001000 */
#define GPIO_CRH_MODE11_1 (0x2U << GPIO_CRH_MODE11_Pos) /* 0x00002000 */
#define GPIO_CRH_CNF11_Pos (14U)
#define GPIO_CRH_CNF11_Msk (0x3U << GPIO_CRH_CNF11_Pos) /* 0x0000C000 */
#define GPIO_CRH_CNF11 GPIO_CRH_CNF11_Msk /* Port n.11 configuration bits */
#define GPIO_CRH_CNF11_0 (0x1U << GPIO_CRH_CNF11_Pos) /* 0x00004000 */
#define GPIO_CRH_CNF11_1 (0x2U << GPIO_CRH_CNF11_Pos) /* 0x00008000 */
#define GPIO_CRH_MODE12_Pos (16U)
#define GPIO_CRH_MODE12_Msk (0x3U << GPIO_CRH_MODE12_Pos) /* 0x00030000 */
#define GPIO_CRH_MODE12 GPIO_CRH_MODE12_Msk /* Port n.12 mode bits */
#define GPIO_CRH_MODE12_0 (0x1U << GPIO_CRH_MODE12_Pos) /* 0x00010000 */
#define GPIO_CRH_MODE12_1 (0x2U << GPIO_CRH_MODE12_Pos) /* 0x00020000 */
#define GPIO_CRH_CNF12_Pos (18U)
#define GPIO_CRH_CNF12_Msk (0x3U << GPIO_CRH_CNF12_Pos) /* 0x000C0000 */
#define GPIO_CRH_CNF12 GPIO_CRH_CNF12_Msk /* Port n.12 configuration bits */
#define GPIO_CRH_CNF12_0 (0x1U << GPIO_CRH_CNF12_Pos) /* 0x00040000 */
#define GPIO_CRH_CNF12_1 (0x2U << GPIO_CRH_CNF12_Pos) /* 0x00080000 */
#define GPIO_CRH_MODE13_Pos (20U)
#define GPIO_CRH_MODE13_Msk (0x3U << GPIO_CRH_MODE13_Pos) /* 0x00300000 */
#define GPIO_CRH_MODE13 GPIO_CRH_MODE13_Msk /* Port n.13 mode bits */
#define GPIO_CRH_MODE13_0 (0x1U << GPIO_CRH_MODE13_Pos) /* 0x00100000 */
#define GPIO_CRH_MODE13_1 (0x2U << GPIO_CRH_MODE13_Pos) /* 0x00200000 */
#define GPIO_CRH_CNF13_Pos (22U)
#define GPIO_CRH_CNF13_Msk (0x3U << GPIO_CRH_CNF13_Pos) /* 0x00C00000 */
#define GPIO_CRH_CNF13 GPIO_CRH_CNF13_Msk /* Port n.13 configuration bits */
#define GPIO_CRH_CNF13_0 (0x1U << GPIO_CRH_CNF13_Pos) /* 0x00400000 */
#define GPIO_CRH_CNF13_1 (0x2U << GPIO_CRH_CNF13_Pos) /* 0x00800000 */
#define GPIO_CRH_MODE14_Pos (24U)
#define GPIO_CRH_MODE14_Msk (0x3U << GPIO_CRH_MODE14_Pos) /* 0x03000000 */
#define GPIO_CRH_MODE14 GPIO_CRH_MODE14_Msk /* Port n.14 mode bits */
#define GPIO_CRH_MODE14_0 (0x1U << GPIO_CRH_MODE14_Pos) /* 0x01000000 */
#define GPIO_CRH_MODE14_1 (0x2U << GPIO_CRH_MODE14_Pos) /* 0x02000000 */
#define GPIO_CRH_CNF14_Pos (26U)
#define GPIO_CRH_CNF14_Msk (0x3U << GPIO_CRH_CNF14_Pos) /* 0x0C000000 */
#define GPIO_CRH_CNF14 GPIO_CRH_CNF14_Msk /* Port n.14 configuration bits */
#define GPIO_CRH_CNF14_0 (0x1U << GPIO_CRH_CNF14_Pos) /* 0x04000000 */
#define GPIO_CRH_CNF14_1 (0x2U << GPIO_CRH_CNF14_Pos) /* 0x08000000 */
#define GPIO_CRH_MODE15_Pos (28U)
#define GPIO_CRH_MODE15_Msk (0x3U << GPIO_CRH_MODE15_Pos) /* 0x30000000 */
#define GPIO_CRH_MODE15 GPIO_CRH_MODE15_Msk /* Port n.15 mode bits */
#define GPIO_CRH_MODE15_0 (0x1U << GPIO_CRH_MODE15_Pos) /* 0x10000000 */
#define GPIO_CRH_MODE15_1 (0x2U << GPIO_CRH_MODE15_Pos) /* 0x20000000 */
#define GPIO_CRH_CNF15_Pos (30U)
#define GPIO_CRH_CNF15_Msk (0x3U << GPIO_CRH_CNF15_Pos) /* 0xC0000000 */
#define GPIO_CRH_CNF15 GPIO_CRH_CNF15_Msk /* Port n.15 configuration bits */
#define GPIO_CRH_CNF15_0 (0x1U << GPIO_CRH_CNF15_Pos) /* 0x40000000 */
#define GPIO_CRH_CNF15_1 (0x2U << GPIO_CRH_CNF15_Pos) /* 0x80000000 */

/* GPIO_IDR */
#define GPIO_IDR_IDR0_Pos (0U)
#define GPIO_IDR_IDR0_Msk (0x1U << GPIO_IDR_IDR0_Pos) /* 0x00000001 */
#define GPIO_IDR_IDR0 GPIO_IDR_IDR0_Msk /* Port input data */
#define GPIO_IDR_IDR1_Pos (1U)
#define GPIO_IDR_IDR1_Msk (0x1U << GPIO_IDR_IDR1_Pos) /* 0x00000002 */
#define GPIO_IDR_IDR1 GPIO_IDR_IDR1_Msk /* Port input data */
#define GPIO_IDR_IDR2_Pos (2U)
#define GPIO_IDR_IDR2_Msk (0x1U << GPIO_IDR_IDR2_Pos) /* 0x00000004 */
#define GPIO_IDR_IDR2 GPIO_IDR_IDR2_Msk /* Port input data */
#define GPIO_IDR_IDR3_Pos (3U)
#define GPIO_IDR_IDR3_Msk (0x1U << GPIO_IDR_IDR3_Pos) /* 0x00000008 */
#define GPIO_IDR_IDR3 GPIO_IDR_IDR3_Msk /* Port input data */
#define GPIO_IDR_IDR4_Pos (4U)
#define GPIO_IDR_IDR4_Msk (0x1U << GPIO_IDR_IDR4_Pos) /* 0x00000010 */
#define GPIO_IDR_IDR4 GPIO_IDR_IDR4_Msk /* Port input data */
#define GPIO_IDR_IDR5_Pos (5U)
#define GPIO_IDR_IDR5_Msk (0x1U << GPIO_IDR_IDR5_Pos) /* 0x00000020 */
#define GPIO_IDR_IDR5 GPIO_IDR_IDR5_Msk /* Port input data */
#define GPIO_IDR_IDR6_Pos (6U)
#define GPIO_IDR_IDR6_Msk (0x1U << GPIO_IDR_IDR6_Pos) /* 0x00000040 */
#define GPIO_IDR_IDR6 GPIO_IDR_IDR6_Msk /* Port input data */
#define GPIO_IDR_IDR7_Pos (7U)
#define GPIO_IDR_IDR7_Msk (0x1U << GPIO_IDR_IDR7_Pos) /* 0x00000080 */
#define GPIO_IDR_IDR7 GPIO_IDR_IDR7_Msk /* Port input data */
#define GPIO_IDR_IDR8_Pos (8U)
#define GPIO_IDR_IDR8_Msk (0x1U << GPIO_IDR_IDR8_Pos) /* 0x00000100 */
#define GPIO_IDR_IDR8 GPIO_IDR_IDR8_Msk /* Port input data */
#define GPIO_IDR_IDR9_Pos (9U)
#define GPIO_IDR_IDR9_Msk (0x1U << GPIO_IDR_IDR9_Pos) /* 0x00000200 */
#define GPIO_IDR_IDR9 GPIO_IDR_IDR9_Msk /* Port input data */
#define GPIO_IDR_IDR10_Pos (10U)
#define GPIO_IDR_IDR10_Msk (0x1U << GPIO_IDR_IDR10_Pos) /* 0x00000400 */
#define GPIO_IDR_IDR10 GPIO_IDR_IDR10_Msk /* Port input data */
#define GPIO_IDR_IDR11_Pos (11U)
#define GPIO_IDR_IDR11_Msk (0x1U << GPIO_IDR_IDR11_Pos) /* 0x00000800 */
#define GPIO_IDR_IDR11 GPIO_IDR_IDR11_Msk /* Port input data */
#define GPIO_IDR_IDR12_Pos (12U)
#define GPIO_IDR_IDR12_Msk (0x1U << GPIO_IDR_IDR12_Pos) /* 0x00001000 */
#define GPIO_IDR_IDR12 GPIO_IDR_IDR12_Msk /* Port input data */
#define GPIO_IDR_IDR13_Pos (13U)
#define GPIO_IDR_IDR13_Msk (0x1U << GPIO_IDR_IDR13_Pos) /* 0x00002000 */
#define GPIO_IDR_IDR13 GPIO_IDR_IDR13_Msk /* Port input data */
#define GPIO_IDR_IDR14_Pos (14U)
#define GPIO_IDR_IDR14_Msk (0x1U << GPIO_IDR_IDR14_Pos) /* 0x00004000 */
#define GPIO_IDR_IDR14 GPIO_IDR_IDR14_Msk /* Port input data */
#define GPIO_IDR_IDR15_Pos (15U)
#define GPIO_IDR_IDR15_Msk (0x1U << GPIO_IDR_IDR15_Pos) /* 0x00008000 */
#define GPIO_IDR_IDR15 GPIO_IDR_IDR15_Msk /* Port input data */

/* GPIO_BSRR */
#define GPIO_BSRR_BS0_Pos (0U)
#define GPIO_BSRR_BS0_Msk (0x1U << GPIO_BSRR_BS0_Pos) /* 0x00000001 */
#define GPIO_BSRR_BS0 GPIO_BSRR_BS0_Msk /* Set bit 0 */
#define GPIO_BSRR_BS1_Pos (1U)
#define GPIO_BSRR_BS1_Msk (0x1U << GPIO_BSRR_BS1_Pos) /* 0x00000002 */
#define GPIO_BSRR_BS1 GPIO_BSRR_BS1_Msk /* Set bit 1 */
#define GPIO_BSRR_BS2_Pos (2U)
#define GPIO_BSRR_BS2_Msk (0x1U << GPIO_BSRR_BS2_Pos) /* 0x00000004 */
#define GPIO_BSRR_BS2 GPIO_BSRR_BS2_Msk /* Set bit 1 */
#define GPIO_BSRR_BS3_Pos (3U)
#define GPIO_BSRR_BS3_Msk (0x1U << GPIO_BSRR_BS3_Pos) /* 0x00000008 */
#define GPIO_BSRR_BS3 GPIO_BSRR_BS3_Msk /* Set bit 3 */
#define GPIO_BSRR_BS4_Pos (4U)
#define GPIO_BSRR_BS4_Msk (0x1U << GPIO_BSRR_BS4_Pos) /* 0x00000010 */
#define GPIO_BSRR_BS4 GPIO_BSRR_BS4_Msk /* Set bit 4 */
#define GPIO_BSRR_BS5_Pos (5U)
#define GPIO_BSRR_BS5_Msk (0x1U << GPIO_BSRR_BS5_Pos) /* 0x00000020 */
#define GPIO_BSRR_BS5 GPIO_BSRR_BS5_Msk /* Set bit 5 */
#define GPIO_BSRR_BS6_Pos (6U)
#define GPIO_BSRR_BS6_Msk (0x1U << GPIO_BSRR_BS6_Pos) /* 0x00000040 */
#define GPIO_BSRR_BS6 GPIO_BSRR_BS6_Msk /* Set bit 6 */
#define GPIO_BSRR_BS7_Pos (7U)
#define GPIO_BSRR_BS7_Msk (0x1U << GPIO_BSRR_BS7_Pos) /* 0x00000080 */
#define GPIO_BSRR_BS7 GPIO_BSRR_BS7_Msk /* Set bit 7 */
#define GPIO_BSRR_BS8_Pos (8U)
#define GPIO_BSRR_BS8_Msk (0x1U << GPIO_BSRR_BS8_Pos) /* 0x00000100 */
#define GPIO_BSRR_BS8 GPIO_BSRR_BS8_Msk /* Set bit 8 */
#define GPIO_BSRR_BS9_Pos (9U)
#define GPIO_BSRR_BS9_Msk (0x1U << GPIO_BSRR_BS9_Pos) /* 0x00000200 */
#define GPIO_BSRR_BS9 GPIO_BSRR_BS9_Msk /* Set bit 9 */
#define GPIO_BSRR_BS10_Pos (10U)
#define GPIO_BSRR_BS10_Msk (0x1U << GPIO_BSRR_BS10_Pos) /* 0x00000400 */
#define GPIO_BSRR_BS10 GPIO_BSRR_BS10_Msk /* Set bit 10 */
#define GPIO_BSRR_BS11_Pos (11U)
#define GPIO_BSRR_BS11_Msk (0x1U << GPIO_BSRR_BS11_Pos) /* 0x00000800 */
#define GPIO_BSRR_BS11 GPIO_BSRR_BS11_Msk /* Set bit 11 */
#define GPIO_BSRR_BS12_Pos (12U)
#define GPIO_BSRR_BS12_Msk (0x1U << GPIO_BSRR_BS12_Pos) /* 0x00001000 */
#define GPIO_BSRR_BS12 GPIO_BSRR_BS12_Msk /* Set bit 12 */
#define GPIO_BSRR_BS13_Pos (13U)
#define GPIO_BSRR_BS13_Msk (0x1U << GPIO_BSRR_BS13_Pos) /* 0x00002000 */
#define GPIO_BSRR_BS13 GPIO_BSRR_BS13_Msk /* Set bit 13 */
#define GPIO_BSRR_BS14_Pos (14U)
#define GPIO_BSRR_BS14_Msk (0x1U << GPIO_BSRR_BS14_Pos) /* 0x00004000 */
#define GPIO_BSRR_BS14 GPIO_BSRR_BS14_Msk /* Set bit 14 */
#define GPIO_BSRR_BS15_Pos (15U)
#define GPIO_BSRR_BS15_Msk (0x1U << GPIO_BSRR_BS15_Pos) /* 0x00008000 */
#define GPIO_BSRR_BS15 GPIO_BSRR_BS15_Msk /* Set bit 15 */
#define GPIO_BSRR_BR0_Pos (16U)
#define GPIO_BSRR_BR0_Msk (0x1U << GPIO_BSRR_BR0_Pos) /* 0x00010000 */
#define GPIO_BSRR_BR0 GPIO_BSRR_BR0_Msk /* Reset bit 0 */
#define GPIO_BSRR_BR1_Pos (17U)
#define GPIO_BSRR_BR1_Msk (0x1U << GPIO_BSRR_BR1_Pos) /* 0x00020000 */
#define GPIO_BSRR_BR1 GPIO_BSRR_BR1_Msk /* Reset bit 1 */
#define GPIO_BSRR_BR2_Pos (18U)
#define GPIO_BSRR_BR2_Msk (0x1U << GPIO_BSRR_BR2_Pos) /* 0x00040000 */
#define GPIO_BSRR_BR2 GPIO_BSRR_BR2_Msk /* Reset bit 2 */
#define GPIO_BSRR_BR3_Pos (19U)
#define GPIO_BSRR_BR3_Msk (0x1U << GPIO_BSRR_BR3_Pos) /* 0x00080000 */
#define GPIO_BSRR_BR3 GPIO_BSRR_BR3_Msk /* Reset bit 3 */
#define GPIO_BSRR_BR4_Pos (20U)
#define GPIO_BSRR_BR4_Msk (0x1U << GPIO_BSRR_BR4_Pos) /* 0x00100000 */
#define GPIO_BSRR_BR4 GPIO_BSRR_BR4_Msk /* Reset bit 4 */
#define GPIO_BSRR_BR5_Pos (21U)
#define GPIO_BSRR_BR5_Msk (0x1U << GPIO_BSRR_BR5_Pos) /* 0x00200000 */
#define GPIO_BSRR_BR5 GPIO_BSRR_BR5_Msk /* Reset bit 5 */
#define GPIO_BSRR_BR6_Pos (22U)
#define GPIO_BSRR_BR6_Msk (0x1U << GPIO_BSRR_BR6_Pos) /* 0x00400000 */
#define GPIO_BSRR_BR6 GPIO_BSRR_BR6_Msk /* Reset bit 6 */
#define GPIO_BSRR_BR7_Pos (23U)
#define GPIO_BSRR_BR7_Msk (0x1U << GPIO_BSRR_BR7_Pos) /* 0x00800000 */
#define GPIO_BSRR_BR7 GPIO_BSRR_BR7_Msk /* Reset bit 7 */
#define GPIO_BSRR_BR8_Pos (24U)
#define GPIO_BSRR_BR8_Msk (0x1U << GPIO_BSRR_BR8_Pos) /* 0x01000000 */
#define GPIO_BSRR_BR8 GPIO_BSRR_BR8_Msk /* Reset bit 8 */
#define GPIO_BSRR_BR9_Pos (25U)
#define GPIO_BSRR_BR9_Msk (0x1U << GPIO_BSRR_BR9_Pos) /* 0x02000000 */
#define GPIO_BSRR_BR9 GPIO_BSRR_BR9_Msk /* Reset bit 9 */
#define GPIO_BSRR_BR10_Pos (26U)
#define GPIO_BSRR_BR10_Msk (0x1U << GPIO_BSRR_BR10_Pos) /* 0x04000000 */
#define GPIO_BSRR_BR10 GPIO_BSRR_BR10_Msk /* Reset bit 10 */
#define GPIO_BSRR_BR11_Pos (27U)
#define GPIO_BSRR_BR11_Msk (0x1U << GPIO_BSRR_BR11_Pos) /* 0x08000000 */
#define GPIO_BSRR_BR11 GPIO_BSRR_BR11_Msk /* Reset bit 11 */
#define GPIO_BSRR_BR12_Pos (28U)
#define GPIO_BSRR_BR12_Msk (0x1U << GPIO_BSRR_BR12_Pos) /* 0x10000000 */
#define GPIO_BSRR_BR12 GPIO_BSRR_BR12_Msk /* Reset bit 12 */
#define GPIO_BSRR_BR13_Pos (29U)
#define GPIO_BSRR_BR13_Msk (0x1U << GPIO_BSRR_BR13_Pos) /* 0x20000000 */
#define GPIO_BSRR_BR13 GPIO_BSRR_BR13_Msk /* Reset bit 13 */
#define GPIO_BSRR_BR14_Pos (30U)
#define GPIO_BSRR_BR14_Msk (0x1U << GPIO_BSRR_BR14_Pos) /* 0x40000000 */
#define GPIO_BSRR_BR14 GPIO_BSRR_BR14_Msk /* Reset bit 14 */
#define GPIO_BSRR_BR15_Pos (31U)
#define GPIO_BSRR_BR15_Msk (0x1U << GPIO_BSRR_BR15_Pos) /* 0x80000000 */
#define GPIO_BSRR_BR15 GPIO_BSRR_BR15_Msk /* Reset bit 15 */

/* ADC_SR */
#define ADC_SR_AWD_Pos (0U)
#define ADC_SR_AWD_Msk (0x1U << ADC_SR_AWD_Pos) /* 0x00000001 */
#define ADC_SR_AWD ADC_SR_AWD_Msk /* Analog watchdog flag */
#define ADC_SR_EOC_Pos (1U)
#define ADC_SR_EOC_Msk (0x1U << ADC_SR_EOC_Pos) /* 0x00000002 */
#define ADC_SR_EOC ADC_SR_EOC_Msk /* Regular channel end of conversion */
#define ADC_SR_JEOC_Pos (2U)
#define ADC_SR_JEOC_Msk (0x1U << ADC_SR_JEOC_Pos) /* 0x00000004 */
#define ADC_SR_JEOC ADC_SR_JEOC_Msk /* Injected channel end of conversion */
#define ADC_SR_JSTRT_Pos (3U)
#define ADC_SR_JSTRT_Msk (0x1U << ADC_SR_JSTRT_Pos) /* 0x00000008 */
#define ADC_SR_JSTRT ADC_SR_JSTRT_Msk /* Injected channel start flag */
#define ADC_SR_STRT_Pos (4U)
#define ADC_SR_STRT_Msk (0x1U << ADC_SR_STRT_Pos) /* 0x00000010 */
#define ADC_SR_STRT ADC_SR_STRT_Msk /* Regular channel start flag */

/* ADC_CR1 */
#define ADC_CR1_AWDCH_Pos (0U)
#define ADC_CR1_AWDCH_Msk (0x1fU << ADC_CR1_AWDCH_Pos) /* 0x0000001F */
#define ADC_CR1_AWDCH ADC_CR1_AWDCH_Msk /* Analog watchdog channel select bits */
#define ADC_CR1_AWDCH_0 (0x1U << ADC_CR1_AWDCH_Pos) /* 0x00000001 */
#define ADC_CR1_AWDCH_1 (0x2U << ADC_CR1_AWDCH_Pos) /* 0x00000002 */
#define ADC_CR1_AWDCH_2 (0x4U << ADC_CR1_AWDCH_Pos) /* 0x00000004 */
#define ADC_CR1_AWDCH_3 (0x8U << ADC_CR1_AWDCH_Pos) /* 0x00000008 */
#define ADC_CR1_AWDCH_4 (0x10U << ADC_CR1_AWDCH_Pos) /* 0x00000010 */
#define ADC_CR1_EOCIE_Pos (5U)
#define ADC_CR1_EOCIE_Msk (0x1U << ADC_CR1_EOCIE_Pos) /* 0x00000020 */
#define ADC_CR1_EOCIE ADC_CR1_EOCIE_Msk /* Interrupt enable for EOC */
#define ADC_CR1_AWDIE_Pos (6U)
#define ADC_CR1_AWDIE_Msk (0x1U << ADC_CR1_AWDIE_Pos) /* 0x00000040 */
#define ADC_CR1_AWDIE ADC_CR1_AWDIE_Msk /* Analog watchdog interrupt enable */
#define ADC_CR1_JEOCIE_Pos (7U)
#define ADC_CR1_JEOCIE_Msk (0x1U << ADC_CR1_JEOCIE_Pos) /* 0x00000080 */
#define ADC_CR1_JEOCIE ADC_CR1_JEOCIE_Msk /* Interrupt enable for injected channels */
#define ADC_CR1_SCAN_Pos (8U)
#define ADC_CR1_SCAN_Msk (0x1U << ADC_CR1_SCAN_Pos) /* 0x00000100 */
#define ADC_CR1_SCAN ADC_CR1_SCAN_Msk /* Scan mode */
#define ADC_CR1_AWDSGL_Pos (9U)
#define ADC_CR1_AWDSGL_Msk (0x1U << ADC_CR1_AWDSGL_Pos) /* 0x00000200 */
#define ADC_CR1_AWDSGL ADC_CR1_AWDSGL_Msk /* Enable the watchdog on a single channel in scan mode */
#define ADC_CR1_JAUTO_Pos (10U)
#define ADC_CR1_JAUTO_Msk (0x1U << ADC_CR1_JAUTO_Pos) /* 0x00000400 */
#define ADC_CR1_JAUTO ADC_CR1_JAUTO_Msk /* Automatic injected group conversion */
#define ADC_CR1_DISCEN_Pos (11U)
#define ADC_CR1_DISCEN_Msk (0x1U << ADC_CR1_DISCEN_Pos) /* 0x00000800 */
#define ADC_CR1_DISCEN ADC_CR1_DISCEN_Msk /* Discontinuous mode on regular channels */
#define ADC_CR1_JDISCEN_Pos (12U)
#define ADC_CR1_JDISCEN_Msk (0x1U << ADC_CR1_JDISCEN_Pos) /* 0x00001000 */
#define ADC_CR1_JDISCEN ADC_CR1_JDISCEN_Msk /* Discontinuous mode on injected channels */
#define ADC_CR1_DISCNUM_Pos (13U)
#define ADC_CR1_DISCNUM_Msk (0x7U << ADC_CR1_DISCNUM_Pos) /* 0x0000E000 */
#define ADC_CR1_DISCNUM ADC_CR1_DISCNUM_Msk /* Discontinuous mode channel count */
#define ADC_CR1_DISCNUM_0 (0x1U << ADC_CR1_DISCNUM_Pos) /* 0x00002000 */
#define ADC_CR1_DISCNUM_1 (0x2U << ADC_CR1_DISCNUM_Pos) /* 0x00004000 */
#define ADC_CR1_DISCNUM_2 (0x4U << ADC_CR1_DISCNUM_Pos) /* 0x00008000 */
#define ADC_CR1_DUALMOD_Pos (16U)
#define ADC_CR1_DUALMOD_Msk (0xfU << ADC_CR1_DUALMOD_Pos) /* 0x000F0000 */
#define ADC_CR1_DUALMOD ADC_CR1_DUALMOD_Msk /* Dual mode selection */
#define ADC_CR1_DUALMOD_0 (0x1U << ADC_CR1_DUALMOD_Pos) /* 0x00010000 */
#define ADC_CR1_DUALMOD_1 (0x2U << ADC_CR1_DUALMOD_Pos) /* 0x00020000 */
#define ADC_CR1_DUALMOD_2 (0x4U << ADC_CR1_DUALMOD_Pos) /* 0x00040000 */
#define ADC_CR1_DUALMOD_3 (0x8U << ADC_CR1_DUALMOD_Pos) /* 0x00080000 */
#define ADC_CR1_JAWDEN_Pos (22U)
#define ADC_CR1_JAWDEN_Msk (0x1U << ADC_CR1_JAWDEN_Pos) /* 0x00400000 */
#define ADC_CR1_JAWDEN ADC_CR1_JAWDEN_Msk /* Analog watchdog enable on injected channels */
#define ADC_CR1_AWDEN_Pos (23U)
#define ADC_CR1_AWDEN_Msk (0x1U << ADC_CR1_AWDEN_Pos) /* 0x00800000 */
#define ADC_CR1_AWDEN ADC_CR1_AWDEN_Msk /* Analog watchdog enable on regular channels */

/* ADC_CR2 */
#define ADC_CR2_ADON_Pos (0U)
#define ADC_CR2_ADON_Msk (0x1U << ADC_CR2_ADON_Pos) /* 0x00000001 */
#define ADC_CR2_ADON ADC_CR2_ADON_Msk /* A/D converter ON / OFF */
#define ADC_CR2_CONT_Pos (1U)
#define ADC_CR2_CONT_Msk (0x1U << ADC_CR2_CONT_Pos) /* 0x00000002 */
#define ADC_CR2_CONT ADC_CR2_CONT_Msk /* Continuous conversion */
#define ADC_CR2_CAL_Pos (2U)
#define ADC_CR2_CAL_Msk (0x1U << ADC_CR2_CAL_Pos) /* 0x00000004 */
#define ADC_CR2_CAL ADC_CR2_CAL_Msk /* A/D calibration */
#define ADC_CR2_RSTCAL_Pos (3U)
#define ADC_CR2_RSTCAL_Msk (0x1U << ADC_CR2_RSTCAL_Pos) /* 0x00000008 */
#define ADC_CR2_RSTCAL ADC_CR2_RSTCAL_Msk /* Reset calibration */
#define ADC_CR2_DMA_Pos (8U)
#define ADC_CR2_DMA_Msk (0x1U << ADC_CR2_DMA_Pos) /* 0x00000100 */
#define ADC_CR2_DMA ADC_CR2_DMA_Msk /* Direct memory access mode */
#define ADC_CR2_ALIGN_Pos (11U)
#define ADC_CR2_ALIGN_Msk (0x1U << ADC_CR2_ALIGN_Pos) /* 0x00000800 */
#define ADC_CR2_ALIGN ADC_CR2_ALIGN_Msk /* Data alignment */
#define ADC_CR2_JEXTSEL_Pos (12U)
#define ADC_CR2_JEXTSEL_Msk (0x7U << ADC_CR2_JEXTSEL_Pos) /* 0x00007000 */
#define ADC_CR2_JEXTSEL ADC_CR2_JEXTSEL_Msk /* External event select for injected group */
#define ADC_CR2_JEXTSEL_0 (0x1U << ADC_CR2_JEXTSEL_Pos) /* 0x00001000 */
#define ADC_CR2_JEXTSEL_1 (0x2U << ADC_CR2_JEXTSEL_Pos) /* 0x00002000 */
#define ADC_CR2_JEXTSEL_2 (0x4U << ADC_CR2_JEXTSEL_Pos) /* 0x00004000 */
#define ADC_CR2_JEXTTRIG_Pos (15U)
#define ADC_CR2_JEXTTRIG_Msk (0x1U << ADC_CR2_JEXTTRIG_Pos) /* 0x00008000 */
#define ADC_CR2_JEXTTRIG ADC_CR2_JEXTTRIG_Msk /* External trigger conversion mode for injected channels */
#define ADC_CR2_EXTSEL_Pos (17U)
#define ADC_CR2_EXTSEL_Msk (0x7U << ADC_CR2_EXTSEL_Pos) /* 0x000E0000 */
#define ADC_CR2_EXTSEL ADC_CR2_EXTSEL_Msk /* External event select for regular group */
#define ADC_CR2_EXTSEL_0 (0x1U << ADC_CR2_EXTSEL_Pos) /* 0x00020000 */
#define ADC_CR2_EXTSEL_1 (0x2U << ADC_CR2_EXTSEL_Pos) /* 0x00040000 */
#define ADC_CR2_EXTSEL_2 (0x4U << ADC_CR2_EXTSEL_Pos) /* 0x00080000 */
#define ADC_CR2_EXTTRIG_Pos (20U)
#define ADC_CR2_EXTTRIG_Msk (0x1U << ADC_CR2_EXTTRIG_Pos) /* 0x00100000 */
#define ADC_CR2_EXTTRIG ADC_CR2_EXTTRIG_Msk /* External trigger conversion mode for regular channels */
#define ADC_CR2_JSWSTART_Pos (21U)
#define ADC_CR2_JSWSTART_Msk (0x1U << ADC_CR2_JSWSTART_Pos) /* 0x00200000 */
#define ADC_CR2_JSWSTART ADC_CR2_JSWSTART_Msk /* Start conversion of injected channels */
#define ADC_CR2_SWSTART_Pos (22U)
#define ADC_CR2_SWSTART_Msk (0x1U << ADC_CR2_SWSTART_Pos) /* 0x00400000 */
#define ADC_CR2_SWSTART ADC_CR2_SWSTART_Msk /* Start conversion of regular channels */
#define ADC_CR2_TSVREFE_Pos (23U)
#define ADC_CR2_TSVREFE_Msk (0x1U << ADC_CR2_TSVREFE_Pos) /* 0x00800000 */
#define ADC_CR2_TSVREFE ADC_CR2_TSVREFE_Msk /* Temperature sensor and VREFINT enable */

/* ADC_SMPR1 */
#define ADC_SMPR1_SMP10_Pos (0U)
#define ADC_SMPR1_SMP10_Msk (0x7U << ADC_SMPR1_SMP10_Pos) /* 0x00000007 */
#define ADC_SMPR1_SMP10 ADC_SMPR1_SMP10_Msk /* Channel 10 sample time selection */
#define ADC_SMPR1_SMP10_0 (0x1U << ADC_SMPR1_SMP10_Pos) /* 0x00000001 */
#define ADC_SMPR1_SMP10_1 (0x2U << ADC_SMPR1_SMP10_Pos) /* 0x00000002 */
#define ADC_SMPR1_SMP10_2 (0x4U << ADC_SMPR1_SMP10_Pos) /* 0x00000004 */
#define ADC_SMPR1_SMP11_Pos (3U)
#define ADC_SMPR1_SMP11_Msk (0x7U << ADC_SMPR1_SMP11_Pos) /* 0x00000038 */
#define ADC_SMPR1_SMP11 ADC_SMPR1_SMP11_Msk /* Channel 11 sample time selection */
#define ADC_SMPR1_SMP11_0 (0x1U << ADC_SMPR1_SMP11_Pos) /* 0x00000008 */
#define ADC_SMPR1_SMP11_1 (0x2U << ADC_SMPR1_SMP11_Pos) /* 0x00000010 */
#define ADC_SMPR1_SMP11_2 (0x4U << ADC_SMPR1_SMP11_Pos) /* 0x00000020 */
#define ADC_SMPR1_SMP12_Pos (6U)
#define ADC_SMPR1_SMP12_Msk (0x7U << ADC_SMPR1_SMP12_Pos) /* 0x000001C0 */
#define ADC_SMPR1_SMP12 ADC_SMPR1_SMP12_Msk /* Channel 12 sample time selection */
#define ADC_SMPR1_SMP12_0 (0x1U << ADC_SMPR1_SMP12_Pos) /* 0x00000040 */
#define ADC_SMPR1_SMP12_1 (0x2U << ADC_SMPR1_SMP12_Pos) /* 0x00000080 */
#define ADC_SMPR1_SMP12_2 (0x4U << ADC_SMPR1_SMP12_Pos) /* 0x00000100 */
#define ADC_SMPR1_SMP13_Pos (9U)
#define ADC_SMPR1_SMP13_Msk (0x7U << ADC_SMPR1_SMP13_Pos) /* 0x00000E00 */
#define ADC_SMPR1_SMP13 ADC_SMPR1_SMP13_Msk /* Channel 13 sample time selection */
#define ADC_SMPR1_SMP13_0 (0x1U << ADC_SMPR1_SMP13_Pos) /* 0x00000200 */
#define ADC_SMPR1_SMP13_1 (0x2U << ADC_SMPR1_SMP13_Pos) /* 0x00000400 */
#define ADC_SMPR1_SMP13_2 (0x4U << ADC_SMPR1_SMP13_Pos) /* 0x00000800 */
#define ADC_SMPR1_SMP14_Pos (12U)
#define ADC_SMPR1_SMP14_Msk (0x7U << ADC_SMPR1_SMP14_Pos) /* 0x00007000 */
#define ADC_SMPR1_SMP14 ADC_SMPR1_SMP14_Msk /* Channel 14 sample time selection */
#define ADC_SMPR1_SMP14_0 (0x1U << ADC_SMPR1_SMP14_Pos) /* 0x00001000 */
#define ADC_SMPR1_SMP14_1 (0x2U << ADC_SMPR1_SMP14_Pos) /* 0x00002000 */
#define ADC_SMPR1_SMP14_2 (0x4U << ADC_SMPR1_SMP14_Pos) /* 0x00004000 */
#define ADC_SMPR1_SMP15_Pos (15U)
#define ADC_SMPR1_SMP15_Msk (0x7U << ADC_SMPR1_SMP15_Pos) /* 0x00038000 */
#define ADC_SMPR1_SMP15 ADC_SMPR1_SMP15_Msk /* Channel 15 sample time selection */
#define ADC_SMPR1_SMP15_0 (0x1U << ADC_SMPR1_SMP15_Pos) /* 0x00008000 */
#define ADC_SMPR1_SMP15_1 (0x2U << ADC_SMPR1_SMP15_Pos) /* 0x00010000 */
#define ADC_SMPR1_SMP15_2 (0x4U << ADC_SMPR1_SMP15_Pos) /* 0x00020000 */
#define ADC_SMPR1_SMP16_Pos (18U)
#define ADC_SMPR1_SMP16_Msk (0x7U << ADC_SMPR1_SMP16_Pos) /* 0x001C0000 */
#define ADC_SMPR1_SMP16 ADC_SMPR1_SMP16_Msk /* Channel 16 sample time selection */
#define ADC_SMPR1_SMP16_0 (0x1U << ADC_SMPR1_SMP16_Pos) /* 0x00040000 */
#define ADC_SMPR1_SMP16_1 (0x2U << ADC_SMPR1_SMP16_Pos) /* 0x00080000 */
#define ADC_SMPR1_SMP16_2 (0x4U << ADC_SMPR1_SMP16_Pos) /* 0x00100000 */
#define ADC_SMPR1_SMP17_Pos (21U)
#define ADC_SMPR1_SMP17_Msk (0x7U << ADC_SMPR1_SMP17_Pos) /* 0x00E00000 */
#define ADC_SMPR1_SMP17 ADC_SMPR1_SMP17_Msk /* Channel 17 sample time selection */
#define ADC_SMPR1_SMP17_0 (0x1U << ADC_SMPR1_SMP17_Pos) /* 0x00200000 */
#define ADC_SMPR1_SMP17_1 (0x2U << ADC_SMPR1_SMP17_Pos) /* 0x00400000 */
#define ADC_SMPR1_SMP17_2 (0x4U << ADC_SMPR1_SMP17_Pos) /* 0x00800000 */

/* ADC_SMPR2 */
#define ADC_SMPR2_SMP0_Pos (0U)
#define ADC_SMPR2_SMP0_Msk (0x7U << ADC_SMPR2_SMP0_Pos) /* 0x00000007 */
#define ADC_SMPR2_SMP0 ADC_SMPR2_SMP0_Msk /* Channel 0 sample time selection */
#define ADC_SMPR2_SMP0_0 (0x1U << ADC_SMPR2_SMP0_Pos) /* 0x00000001 */
#define ADC_SMPR2_SMP0_1 (0x2U << ADC_SMPR2_SMP0_Pos) /* 0x00000002 */
#define ADC_SMPR2_SMP0_2 (0x4U << ADC_SMPR2_SMP0_Pos) /* 0x00000004 */
#define ADC_SMPR2_SMP1_Pos (3U)
#define ADC_SMPR2_SMP1_Msk (0x7U << ADC_SMPR2_SMP1_Pos) /* 0x00000038 */
#define ADC_SMPR2_SMP1 ADC_SMPR2_SMP1_Msk /* Channel 1 sample time selection */
#define ADC_SMPR2_SMP1_0 (0x1U << ADC_SMPR2_SMP1_Pos) /* 0x00000008 */
#define ADC_SMPR2_SMP1_1 (0x2U << ADC_SMPR2_SMP1_Pos) /* 0x00000010 */
#define ADC_SMPR2_SMP1_2 (0x4U << ADC_SMPR2_SMP1_Pos) /* 0x00000020 */
#define ADC_SMPR2_SMP2_Pos (6U)
#define ADC_SMPR2_SMP2_Msk (0x7U << ADC_SMPR2_SMP2_Pos) /* 0x000001C0 */
#define ADC_SMPR2_SMP2 ADC_SMPR2_SMP2_Msk /* Channel 2 sample time selection */
#define ADC_SMPR2_SMP2_0 (0x1U << ADC_SMPR2_SMP2_Pos) /* 0x00000040 */
#define ADC_SMPR2_SMP2_1 (0x2U << ADC_SMPR2_SMP2_Pos) /* 0x00000080 */
#define ADC_SMPR2_SMP2_2 (0x4U << ADC_SMPR2_SMP2_Pos) /* 0x00000100 */
#define ADC_SMPR2_SMP3_Pos (9U)
#define ADC_SMPR2_SMP3_Msk (0x7U << ADC_SMPR2_SMP3_Pos) /* 0x00000E00 */
#define ADC_SMPR2_SMP3 ADC_SMPR2_SMP3_Msk /* Channel 3 sample time selection */
#define ADC_SMPR2_SMP3_0 (0x1U << ADC_SMPR2_SMP3_Pos) /* 0x00000200 */
#define ADC_SMPR2_SMP3_1 (0x2U << ADC_SMPR2_SMP3_Pos) /* 0x00000400 */
#define ADC_SMPR2_SMP3_2 (0x4U << ADC_SMPR2_SMP3_Pos) /* 0x00000800 */
#define ADC_SMPR2_SMP4_Pos (12U)
#define ADC_SMPR2_SMP4_Msk (0x7U << ADC_SMPR2_SMP4_Pos) /* 0x00007000 */
#define ADC_SMPR2_SMP4 ADC_SMPR2_SMP4_Msk /* Channel 4 sample time selection */
#define ADC_SMPR2_SMP4_0 (0x1U << ADC_SMPR2_SMP4_Pos) /* 0x00001000 */
#define ADC_SMPR2_SMP4_1 (0x2U << ADC_SMPR2_SMP4_Pos) /* 0x00002000 */
#define ADC_SMPR2_SMP4_2 (0x4U << ADC_SMPR2_SMP4_Pos) /* 0x00004000 */
#define ADC_SMPR2_SMP5_Pos (15U)
#define ADC_SMPR2_SMP5_Msk (0x7U << ADC_SMPR2_SMP5_Pos) /* 0x00038000 */
#define ADC_SMPR2_SMP5 ADC_SMPR2_SMP5_Msk /* Channel 5 sample time selection */
#define ADC_SMPR2_SMP5_0 (0x1U << ADC_SMPR2_SMP5_Pos) /* 0x00008000 */
#define ADC_SMPR2_SMP5_1 (0x2U << ADC_SMPR2_SMP5_Pos) /* 0x00010000 */
#define ADC_SMPR2_SMP5_2 (0x4U << ADC_SMPR2_SMP5_Pos) /* 0x00020000 */
#define ADC_SMPR2_SMP6_Pos (18U)
#define ADC_SMPR2_SMP6_Msk (0x7U << ADC_SMPR2_SMP6_Pos) /* 0x001C0000 */
#define ADC_SMPR2_SMP6 ADC_SMPR2_SMP6_Msk /* Channel 6 sample time selection */
#define ADC_SMPR2_SMP6_0 (0x1U << ADC_SMPR2_SMP6_Pos) /* 0x00040000 */
#define ADC_SMPR2_SMP6_1 (0x2U << ADC_SMPR2_SMP6_Pos) /* 0x00080000 */
#define ADC_SMPR2_SMP6_2 (0x4U << ADC_SMPR2_SMP6_Pos) /* 0x00100000 */
#define ADC_SMPR2_SMP7_Pos (21U)
#define ADC_SMPR2_SMP7_Msk (0x7U << ADC_SMPR2_SMP7_Pos) /* 0x00E00000 */
#define ADC_SMPR2_SMP7 ADC_SMPR2_SMP7_Msk /* Channel 7 sample time selection */
#define ADC_SMPR2_SMP7_0 (0x1U << ADC_SMPR2_SMP7_Pos) /* 0x00200000 */
#define ADC_SMPR2_SMP7_1 (0x2U << ADC_SMPR2_SMP7_Pos) /* 0x00400000 */
#define ADC_SMPR2_SMP7_2 (0x4U << ADC_SMPR2_SMP7_Pos) /* 0x00800000 */
#define ADC_SMPR2_SMP8_Pos (24U)
#define ADC_SMPR2_SMP8_Msk (0x7U << ADC_SMPR2_SMP8_Pos) /* 0x07000000 */
#define ADC_SMPR2_SMP8 ADC_SMPR2_SMP8_Msk /* Channel 8 sample time selection */
#define ADC_SMPR2_SMP8_0 (0x1U << ADC_SMPR2_SMP8_Pos) /* 0x01000000 */
#define ADC_SMPR2_SMP8_1 (0x2U << ADC_SMPR2_SMP8_Pos) /* 0x02000000 */
#define ADC_SMPR2_SMP8_2 (0x4U << ADC_SMPR2_SMP8_Pos) /* 0x04000000 */
#define ADC_SMPR2_SMP9_Pos (27U)
#define ADC_SMPR2_SMP9_Msk (0x7U << ADC_SMPR2_SMP9_Pos) /* 0x38000000 */
#define ADC_SMPR2_SMP9 ADC_SMPR2_SMP9_Msk /* Channel 9 sample time selection */
#define ADC_SMPR2_SMP9_0 (0x1U << ADC_SMPR2_SMP9_Pos) /* 0x08000000 */
#define ADC_SMPR2_SMP9_1 (0x2U << ADC_SMPR2_SMP9_Pos) /* 0x10000000 */
#define ADC_SMPR2_SMP9_2 (0x4U << ADC_SMPR2_SMP9_Pos) /* 0x20000000 */

/* ADC_HTR */
#define ADC_HTR_HT_Pos (0U)
#define ADC_HTR_HT_Msk (0xfffU << ADC_HTR_HT_Pos) /* 0x00000FFF */
#define ADC_HTR_HT ADC_HTR_HT_Msk /* Analog watchdog higher threshold */

/* ADC_LTR */
#define ADC_LTR_LT_Pos (0U)
#define ADC_LTR_LT_Msk (0xfffU << ADC_LTR_LT_Pos) /* 0x00000FFF */
#define ADC_LTR_LT ADC_LTR_LT_Msk /* Analog watchdog lower threshold */

/* ADC_SQR1 */
#define ADC_SQR1_SQ13_Pos (0U)
#define ADC_SQR1_SQ13_Msk (0x1fU << ADC_SQR1_SQ13_Pos) /* 0x0000001F */
#define ADC_SQR1_SQ13 ADC_SQR1_SQ13_Msk /* 13th conversion in regular sequence */
#define ADC_SQR1_SQ13_0 (0x1U << ADC_SQR1_SQ13_Pos) /* 0x00000001 */
#define ADC_SQR1_SQ13_1 (0x2U << ADC_SQR1_SQ13_Pos) /* 0x00000002 */
#define ADC_SQR1_SQ13_2 (0x4U << ADC_SQR1_SQ13_Pos) /* 0x00000004 */
#define ADC_SQR1_SQ13_3 (0x8U << ADC_SQR1_SQ13_Pos) /* 0x00000008 */
#define ADC_SQR1_SQ13_4 (0x10U << ADC_SQR1_SQ13_Pos) /* 0x00000010 */
#define ADC_SQR1_SQ14_Pos (5U)
#define ADC_SQR1_SQ14_Msk (0x1fU << ADC_SQR1_SQ14_Pos) /* 0x000003E0 */
#define ADC_SQR1_SQ14 ADC_SQR1_SQ14_Msk /* 14th conversion in regular sequence */
#define ADC_SQR1_SQ14_0 (0x1U << ADC_SQR1_SQ14_Pos) /* 0x00000020 */
#define ADC_SQR1_SQ14_1 (0x2U << ADC_SQR1_SQ14_Pos) /* 0x00000040 */
#define ADC_SQR1_SQ14_2 (0x4U << ADC_SQR1_SQ14_Pos) /* 0x00000080 */
#define ADC_SQR1_SQ14_3 (0x8U << ADC_SQR1_SQ14_Pos) /* 0x00000100 */
#define ADC_SQR1_SQ14_4 (0x10U << ADC_SQR1_SQ14_Pos) /* 0x00000200 */
#define ADC_SQR1_SQ15_Pos (10U)
#define ADC_SQR1_SQ15_Msk (0x1fU << ADC_SQR1_SQ15_Pos) /* 0x00007C00 */
#define ADC_SQR1_SQ15 ADC_SQR1_SQ15_Msk /* 15th conversion in regular sequence */
#define ADC_SQR1_SQ15_0 (0x1U << ADC_SQR1_SQ15_Pos) /* 0x00000400 */
#define ADC_SQR1_SQ15_1 (0x2U << ADC_SQR1_SQ15_Pos) /* 0x00000800 */
#define ADC_SQR1_SQ15_2 (0x4U << ADC_SQR1_SQ15_Pos) /* 0x00001000 */
#define ADC_SQR1_SQ15_3 (0x8U << ADC_SQR1_SQ15_Pos) /* 0x00002000 */
#define ADC_SQR1_SQ15_4 (0x10U << ADC_SQR1_SQ15_Pos) /* 0x00004000 */
#define ADC_SQR1_SQ16_Pos (15U)
#define ADC_SQR1_SQ16_Msk (0x1fU << ADC_SQR1_SQ16_Pos) /* 0x000F8000 */
#define ADC_SQR1_SQ16 ADC_SQR1_SQ16_Msk /* 16th conversion in regular sequence */
#define ADC_SQR1_SQ16_0 (0x1U << ADC_SQR1_SQ16_Pos) /* 0x00008000 */
#define ADC_SQR1_SQ16_1 (0x2U << ADC_SQR1_SQ16_Pos) /* 0x00010000 */
#define ADC_SQR1_SQ16_2 (0x4U << ADC_SQR1_SQ16_Pos) /* 0x00020000 */
#define ADC_SQR1_SQ16_3 (0x8U << ADC_SQR1_SQ16_Pos) /* 0x00040000 */
#define ADC_SQR1_SQ16_4 (0x10U << ADC_SQR1_SQ16_Pos) /* 0x00080000 */
#define ADC_SQR1_L_Pos (20U)
#define ADC_SQR1_L_Msk (0xfU << ADC_SQR1_L_Pos) /* 0x00F00000 */
#define ADC_SQR1_L ADC_SQR1_L_Msk /* Regular channel sequence length */
#define ADC_SQR1_L_0 (0x1U << ADC_SQR1_L_Pos) /* 0x00100000 */
#define ADC_SQR1_L_1 (0x2U << ADC_SQR1_L_Pos) /* 0x00200000 */
#define ADC_SQR1_L_2 (0x4U << ADC_SQR1_L_Pos) /* 0x00400000 */
#define ADC_SQR1_L_3 (0x8U << ADC_SQR1_L_Pos) /* 0x00800000 */

/* ADC_SQR3 */
#define ADC_SQR3_SQ1_Pos (0U)
#define ADC_SQR3_SQ1_Msk (0x1fU << ADC_SQR3_SQ1_Pos) /* 0x0000001F */
#define ADC_SQR3_SQ1 ADC_SQR3_SQ1_Msk /* 1st conversion in regular sequence */
#define ADC_SQR3_SQ1_0 (0x1U << ADC_SQR3_SQ1_Pos) /* 0x00000001 */
#define ADC_SQR3_SQ1_1 (0x2U << ADC_SQR3_SQ1_Pos) /* 0x00000002 */
#define ADC_SQR3_SQ1_2 (0x4U << ADC_SQR3_SQ1_Pos) /* 0x00000004 */
#define ADC_SQR3_SQ1_3 (0x8U << ADC_SQR3_SQ1_Pos) /* 0x00000008 */
#define ADC_SQR3_SQ1_4 (0x10U << ADC_SQR3_SQ1_Pos) /* 0x00000010 */
#define ADC_SQR3_SQ2_Pos (5U)
#define ADC_SQR3_SQ2_Msk (0x1fU << ADC_SQR3_SQ2_Pos) /* 0x000003E0 */
#define ADC_SQR3_SQ2 ADC_SQR3_SQ2_Msk /* 2nd conversion in regular sequence */
#define ADC_SQR3_SQ2_0 (0x1U << ADC_SQR3_SQ2_Pos) /* 0x00000020 */
#define ADC_SQR3_SQ2_1 (0x2U << ADC_SQR3_SQ2_Pos) /* 0x00000040 */
#define ADC_SQR3_SQ2_2 (0x4U << ADC_SQR3_SQ2_Pos) /* 0x00000080 */
#define ADC_SQR3_SQ2_3 (0x8U << ADC_SQR3_SQ2_Pos) /* 0x00000100 */
#define ADC_SQR3_SQ2_4 (0x10U << ADC_SQR3_SQ2_Pos) /* 0x00000200 */
#define ADC_SQR3_SQ3_Pos (10U)
#define ADC_SQR3_SQ3_Msk (0x1fU << ADC_SQR3_SQ3_Pos) /* 0x00007C00 */
#define ADC_SQR3_SQ3 ADC_SQR3_SQ3_Msk /* 3rd conversion in regular sequence */
#define ADC_SQR3_SQ3_0 (0x1U << ADC_SQR3_SQ3_Pos) /* 0x00000400 */
#define ADC_SQR3_SQ3_1 (0x2U << ADC_SQR3_SQ3_Pos) /* 0x00000800 */
#define ADC_SQR3_SQ3_2 (0x4U << ADC_SQR3_SQ3_Pos) /* 0x00001000 */
#define ADC_SQR3_SQ3_3 (0x8U << ADC_SQR3_SQ3_Pos) /* 0x00002000 */
#define ADC_SQR3_SQ3_4 (0x10U << ADC_SQR3_SQ3_Pos) /* 0x00004000 */
#define ADC_SQR3_SQ4_Pos (15U)
#define ADC_SQR3_SQ4_Msk (0x1fU << ADC_SQR3_SQ4_Pos) /* 0x000F8000 */
#define ADC_SQR3_SQ4 ADC_SQR3_SQ4_Msk /* 4th conversion in regular sequence */
#define ADC_SQR3_SQ4_0 (0x1U << ADC_SQR3_SQ4_Pos) /* 0x00008000 */
#define ADC_SQR3_SQ4_1 (0x2U << ADC_SQR3_SQ4_Pos) /* 0x00010000 */
#define ADC_SQR3_SQ4_2 (0x4U << ADC_SQR3_SQ4_Pos) /* 0x00020000 */
#define ADC_SQR3_SQ4_3 (0x8U << ADC_SQR3_SQ4_Pos) /* 0x00040000 */
#define ADC_SQR3_SQ4_4 (0x10U << ADC_SQR3_SQ4_Pos) /* 0x00080000 */
#define ADC_SQR3_SQ5_Pos (20U)
#define ADC_SQR3_SQ5_Msk (0x1fU << ADC_SQR3_SQ5_Pos) /* 0x01F00000 */
#define ADC_SQR3_SQ5 ADC_SQR3_SQ5_Msk /* 5th conversion in regular sequence */
#define ADC_SQR3_SQ5_0 (0x1U << ADC_SQR3_SQ5_Pos) /* 0x00100000 */
#define ADC_SQR3_SQ5_1 (0x2U << ADC_SQR3_SQ5_Pos) /* 0x00200000 */
#define ADC_SQR3_SQ5_2 (0x4U << ADC_SQR3_SQ5_Pos) /* 0x00400000 */
#define ADC_SQR3_SQ5_3 (0x8U << ADC_SQR3_SQ5_Pos) /* 0x00800000 */
#define ADC_SQR3_SQ5_4 (0x10U << ADC_SQR3_SQ5_Pos) /* 0x01000000 */
#define ADC_SQR3_SQ6_Pos (25U)
#define ADC_SQR3_SQ6_Msk (0x1fU << ADC_SQR3_SQ6_Pos) /* 0x3E000000 */
#define ADC_SQR3_SQ6 ADC_SQR3_SQ6_Msk /* 6th conversion in regular sequence */
#define ADC_SQR3_SQ6_0 (0x1U << ADC_SQR3_SQ6_Pos) /* 0x02000000 */
#define ADC_SQR3_SQ6_1 (0x2U << ADC_SQR3_SQ6_Pos) /* 0x04000000 */
#define ADC_SQR3_SQ6_2 (0x4U << ADC_SQR3_SQ6_Pos) /* 0x08000000 */
#define ADC_SQR3_SQ6_3 (0x8U << ADC_SQR3_SQ6_Pos) /* 0x10000000 */
#define ADC_SQR3_SQ6_4 (0x10U << ADC_SQR3_SQ6_Pos) /* 0x20000000 */

/* ADC_JSQR */
#define ADC_JSQR_JSQ1_Pos (0U)
#define ADC_JSQR_JSQ1_Msk (0x1fU << ADC_JSQR_JSQ1_Pos) /* 0x0000001F */
#define ADC_JSQR_JSQ1 ADC_JSQR_JSQ1_Msk /* 1st conversion in injected sequence */
#define ADC_JSQR_JSQ1_0 (0x1U << ADC_JSQR_JSQ1_Pos) /* 0x00000001 */
#define ADC_JSQR_JSQ1_1 (0x2U << ADC_JSQR_JSQ1_Pos) /* 0x00000002 */
#define ADC_JSQR_JSQ1_2 (0x4U << ADC_JSQR_JSQ1_Pos) /* 0x00000004 */
#define ADC_JSQR_JSQ1_3 (0x8U << ADC_JSQR_JSQ1_Pos) /* 0x00000008 */
#define ADC_JSQR_JSQ1_4 (0x10U << ADC_JSQR_JSQ1_Pos) /* 0x00000010 */
#define ADC_JSQR_JSQ2_Pos (5U)
#define ADC_JSQR_JSQ2_Msk (0x1fU << ADC_JSQR_JSQ2_Pos) /* 0x000003E0 */
#define ADC_JSQR_JSQ2 ADC_JSQR_JSQ2_Msk /* 2nd conversion in injected sequence */
#define ADC_JSQR_JSQ2_0 (0x1U << ADC_JSQR_JSQ2_Pos) /* 0x00000020 */
#define ADC_JSQR_JSQ2_1 (0x2U << ADC_JSQR_JSQ2_Pos) /* 0x00000040 */
#define ADC_JSQR_JSQ2_2 (0x4U << ADC_JSQR_JSQ2_Pos) /* 0x00000080 */
#define ADC_JSQR_JSQ2_3 (0x8U << ADC_JSQR_JSQ2_Pos) /* 0x00000100 */
#define ADC_JSQR_JSQ2_4 (0x10U << ADC_JSQR_JSQ2_Pos) /* 0x00000200 */
#define ADC_JSQR_JSQ3_Pos (10U)
#define ADC_JSQR_JSQ3_Msk (0x1fU << ADC_JSQR_JSQ3_Pos) /* 0x00007C00 */
#define ADC_JSQR_JSQ3 ADC_JSQR_JSQ3_Msk /* 3rd conversion in injected sequence */
#define ADC_JSQR_JSQ3_0 (0x1U << ADC_JSQR_JSQ3_Pos) /* 0x00000400 */
#define ADC_JSQR_JSQ3_1 (0x2U << ADC_JSQR_JSQ3_Pos) /* 0x00000800 */
#define ADC_JSQR_JSQ3_2 (0x4U << ADC_JSQR_JSQ3_Pos) /* 0x00001000 */
#define ADC_JSQR_JSQ3_3 (0x8U << ADC_JSQR_JSQ3_Pos) /* 0x00002000 */
#define ADC_JSQR_JSQ3_4 (0x10U << ADC_JSQR_JSQ3_Pos) /* 0x00004000 */
#define ADC_JSQR_JSQ4_Pos (15U)
#define ADC_JSQR_JSQ4_Msk (0x1fU << ADC_JSQR_JSQ4_Pos) /* 0x000F8000 */
#define ADC_JSQR_JSQ4 ADC_JSQR_JSQ4_Msk /* 4th conversion in injected sequence */
#define ADC_JSQR_JSQ4_0 (0x1U << ADC_JSQR_JSQ4_Pos) /* 0x00008000 */
#define ADC_JSQR_JSQ4_1 (0x2U << ADC_JSQR_JSQ4_Pos) /* 0x00010000 */
#define ADC_JSQR_JSQ4_2 (0x4U << ADC_JSQR_JSQ4_Pos) /* 0x00020000 */
#define ADC_JSQR_JSQ4_3 (0x8U << ADC_JSQR_JSQ4_Pos) /* 0x00040000 */
#define ADC_JSQR_JSQ4_4 (0x10U << ADC_JSQR_JSQ4_Pos) /* 0x00080000 */
#define ADC_JSQR_JL_Pos (20U)
#define ADC_JSQR_JL_Msk (0x3U << ADC_JSQR_JL_Pos) /* 0x00300000 */
#define ADC_JSQR_JL ADC_JSQR_JL_Msk /* Injected sequence length */
#define ADC_JSQR_JL_0 (0x1U << ADC_JSQR_JL_Pos) /* 0x00100000 */
#define ADC_JSQR_JL_1 (0x2U << ADC_JSQR_JL_Pos) /* 0x00200000 */

/* ADC_JDR1 */
#define ADC_JDR1_JDATA_Pos (0U)
#define ADC_JDR1_JDATA_Msk (0xffffU << ADC_JDR1_JDATA_Pos) /* 0x0000FFFF */
#define ADC_JDR1_JDATA ADC_JDR1_JDATA_Msk /* Injected data */

/* ADC_JDR2 */
#define ADC_JDR2_JDATA_Pos (0U)
#define ADC_JDR2_JDATA_Msk (0xffffU << ADC_JDR2_JDATA_Pos) /* 0x0000FFFF */
#define ADC_JDR2_JDATA ADC_JDR2_JDATA_Msk /* Injected data */

/* ADC_JDR3 */
#define ADC_JDR3_JDATA_Pos (0U)
#define ADC_JDR3_JDATA_Msk (0xffffU << ADC_JDR3_JDATA_Pos) /* 0x0000FFFF */
#define ADC_JDR3_JDATA ADC_JDR3_JDATA_Msk /* Injected data */

/* ADC_JDR4 */
#define ADC_JDR4_JDATA_Pos (0U)
#define ADC_JDR4_JDATA_Msk (0xffffU << ADC_JDR4_JDATA_Pos) /* 0x0000FFFF */
#define ADC_JDR4_JDATA ADC_JDR4_JDATA_Msk /* Injected data */

/* ADC_DR */
#define ADC_DR_DATA_Pos (0U)
#define ADC_DR_DATA_Msk (0xffffU << ADC_DR_DATA_Pos) /* 0x0000FFFF */
#define ADC_DR_DATA ADC_DR_DATA_Msk /* Regular data */
#define ADC_DR_ADC2DATA_Pos (16U)
#define ADC_DR_ADC2DATA_Msk (0xffffU << ADC_DR_ADC2DATA_Pos) /* 0xFFFF0000 */
#define ADC_DR_ADC2DATA ADC_DR_ADC2DATA_Msk /* ADC2 data */

/* FLASH_ACR */
#define FLASH_ACR_LATENCY_Pos (0U)
#define FLASH_ACR_LATENCY_Msk (0x7U << FLASH_ACR_LATENCY_Pos) /* 0x00000007 */
#define FLASH_ACR_LATENCY FLASH_ACR_LATENCY_Msk /* Latency */
#define FLASH_ACR_LATENCY_0 (0x1U << FLASH_ACR_LATENCY_Pos) /* 0x00000001 */
#define FLASH_ACR_LATENCY_1 (0x2U << FLASH_ACR_LATENCY_Pos) /* 0x00000002 */
#define FLASH_ACR_LATENCY_2 (0x4U << FLASH_ACR_LATENCY_Pos) /* 0x00000004 */
#define FLASH_ACR_HLFCYA_Pos (3U)
#define FLASH_ACR_HLFCYA_Msk (0x1U << FLASH_ACR_HLFCYA_Pos) /* 0x00000008 */
#define FLASH_ACR_HLFCYA FLASH_ACR_HLFCYA_Msk /* Flash half cycle access enable */
#define FLASH_ACR_PRFTBE_Pos (4U)
#define FLASH_ACR_PRFTBE_Msk (0x1U << FLASH_ACR_PRFTBE_Pos) /* 0x00000010 */
#define FLASH_ACR_PRFTBE FLASH_ACR_PRFTBE_Msk /* Prefetch buffer enable */
#define FLASH_ACR_PRFTBS_Pos (5U)
#define FLASH_ACR_PRFTBS_Msk (0x1U << FLASH_ACR_PRFTBS_Pos) /* 0x00000020 */
#define FLASH_ACR_PRFTBS FLASH_ACR_PRFTBS_Msk /* Prefetch buffer status */

/* IWDG_KR */
#define IWDG_KR_KEY_Pos (0U)
#define IWDG_KR_KEY_Msk (0xffffU << IWDG_KR_KEY_Pos) /* 0x0000FFFF */
#define IWDG_KR_KEY IWDG_KR_KEY_Msk /* Key value */

/* IWDG_PR */
#define IWDG_PR_PR_Pos (0U)
#define IWDG_PR_PR_Msk (0x7U << IWDG_PR_PR_Pos) /* 0x00000007 */
#define IWDG_PR_PR IWDG_PR_PR_Msk /* Prescaler divider */
#define IWDG_PR_PR_0 (0x1U << IWDG_PR_PR_Pos) /* 0x00000001 */
#define IWDG_PR_PR_1 (0x2U << IWDG_PR_PR_Pos) /* 0x00000002 */
#define IWDG_PR_PR_2 (0x4U << IWDG_PR_PR_Pos) /* 0x00000004 */

/* IWDG_RLR */
#define IWDG_RLR_RL_Pos (0U)
#define IWDG_RLR_RL_Msk (0xfffU << IWDG_RLR_RL_Pos) /* 0x00000FFF */
#define IWDG_RLR_RL IWDG_RLR_RL_Msk /* Watchdog counter reload value */

/* IWDG_SR */
#define IWDG_SR_PVU_Pos (0U)
#define IWDG_SR_PVU_Msk (0x1U << IWDG_SR_PVU_Pos) /* 0x00000001 */
#define IWDG_SR_PVU IWDG_SR_PVU_Msk /* Watchdog prescaler value update */
#define IWDG_SR_RVU_Pos (1U)
#define IWDG_SR_RVU_Msk (0x1U << IWDG_SR_RVU_Pos) /* 0x00000002 */
#define IWDG_SR_RVU IWDG_SR_RVU_Msk /* Watchdog counter reload value update */

/* AFIO_MAPR */
#define AFIO_MAPR_SPI1_REMAP_Pos (0U)
#define AFIO_MAPR_SPI1_REMAP_Msk (0x1U << AFIO_MAPR_SPI1_REMAP_Pos) /* 0x00000001 */
#define AFIO_MAPR_SPI1_REMAP AFIO_MAPR_SPI1_REMAP_Msk /* SPI1 remapping */
#define AFIO_MAPR_I2C1_REMAP_Pos (1U)
#define AFIO_MAPR_I2C1_REMAP_Msk (0x1U << AFIO_MAPR_I2C1_REMAP_Pos) /* 0x00000002 */
#define AFIO_MAPR_I2C1_REMAP AFIO_MAPR_I2C1_REMAP_Msk /* I2C1 remapping */
#define AFIO_MAPR_USART1_REMAP_Pos (2U)
#define AFIO_MAPR_USART1_REMAP_Msk (0x1U << AFIO_MAPR_USART1_REMAP_Pos) /* 0x00000004 */
#define AFIO_MAPR_USART1_REMAP AFIO_MAPR_USART1_REMAP_Msk /* USART1 remapping */
#define AFIO_MAPR_USART2_REMAP_Pos (3U)
#define AFIO_MAPR_USART2_REMAP_Msk (0x1U << AFIO_MAPR_USART2_REMAP_Pos) /* 0x00000008 */
#define AFIO_MAPR_USART2_REMAP AFIO_MAPR_USART2_REMAP_Msk /* USART2 remapping */
#define AFIO_MAPR_USART3_REMAP_Pos (4U)
#define AFIO_MAPR_USART3_REMAP_Msk (0x3U << AFIO_MAPR_USART3_REMAP_Pos) /* 0x00000030 */
#define AFIO_MAPR_USART3_REMAP AFIO_MAPR_USART3_REMAP_Msk /* USART3 remapping */
#define AFIO_MAPR_USART3_REMAP_0 (0x1U << AFIO_MAPR_USART3_REMAP_Pos) /* 0x00000010 */
#define AFIO_MAPR_USART3_REMAP_1 (0x2U << AFIO_MAPR_USART3_REMAP_Pos) /* 0x00000020 */
#define AFIO_MAPR_TIM1_REMAP_Pos (6U)
#define AFIO_MAPR_TIM1_REMAP_Msk (0x3U << AFIO_MAPR_TIM1_REMAP_Pos) /* 0x000000C0 */
#define AFIO_MAPR_TIM1_REMAP AFIO_MAPR_TIM1_REMAP_Msk /* TIM1 remapping */
#define AFIO_MAPR_TIM1_REMAP_0 (0x1U << AFIO_MAPR_TIM1_REMAP_Pos) /* 0x00000040 */
#define AFIO_MAPR_TIM1_REMAP_1 (0x2U << AFIO_MAPR_TIM1_REMAP_Pos) /* 0x00000080 */
#define AFIO_MAPR_TIM2_REMAP_Pos (8U)
#define AFIO_MAPR_TIM2_REMAP_Msk (0x3U << AFIO_MAPR_TIM2_REMAP_Pos) /* 0x00000300 */
#define AFIO_MAPR_TIM2_REMAP AFIO_MAPR_TIM2_REMAP_Msk /* TIM2 remapping */
#define AFIO_MAPR_TIM2_REMAP_0 (0x1U << AFIO_MAPR_TIM2_REMAP_Pos) /* 0x00000100 */
#define AFIO_MAPR_TIM2_REMAP_1 (0x2U << AFIO_MAPR_TIM2_REMAP_Pos) /* 0x00000200 */
#define AFIO_MAPR_TIM3_REMAP_Pos (10U)
#define AFIO_MAPR_TIM3_REMAP_Msk (0x3U << AFIO_MAPR_TIM3_REMAP_Pos) /* 0x00000C00 */
#define AFIO_MAPR_TIM3_REMAP AFIO_MAPR_TIM3_REMAP_Msk /* TIM3 remapping */
#define AFIO_MAPR_TIM3_REMAP_0 (0x1U << AFIO_MAPR_TIM3_REMAP_Pos) /* 0x00000400 */
#define AFIO_MAPR_TIM3_REMAP_1 (0x2U << AFIO_MAPR_TIM3_REMAP_Pos) /* 0x00000800 */
#define AFIO_MAPR_TIM4_REMAP_Pos (12U)
#define AFIO_MAPR_TIM4_REMAP_Msk (0x1U << AFIO_MAPR_TIM4_REMAP_Pos) /* 0x00001000 */
#define AFIO_MAPR_TIM4_REMAP AFIO_MAPR_TIM4_REMAP_Msk /* TIM4 remapping */
#define AFIO_MAPR_CAN_REMAP_Pos (13U)
#define AFIO_MAPR_CAN_REMAP_Msk (0x3U << AFIO_MAPR_CAN_REMAP_Pos) /* 0x00006000 */
#define AFIO_MAPR_CAN_REMAP AFIO_MAPR_CAN_REMAP_Msk /* CAN1 remapping */
#define AFIO_MAPR_CAN_REMAP_0 (0x1U << AFIO_MAPR_CAN_REMAP_Pos) /* 0x00002000 */
#define AFIO_MAPR_CAN_REMAP_1 (0x2U << AFIO_MAPR_CAN_REMAP_Pos) /* 0x00004000 */
#define AFIO_MAPR_PD01_REMAP_Pos (15U)
#define AFIO_MAPR_PD01_REMAP_Msk (0x1U << AFIO_MAPR_PD01_REMAP_Pos) /* 0x00008000 */
#define AFIO_MAPR_PD01_REMAP AFIO_MAPR_PD01_REMAP_Msk /* Port D0/Port D1 mapping on OSCIN/OSCOUT */
#define AFIO_MAPR_TIM5CH4_IREMAP_Pos (16U)
#define AFIO_MAPR_TIM5CH4_IREMAP_Msk (0x1U << AFIO_MAPR_TIM5CH4_IREMAP_Pos) /* 0x00010000 */
#define AFIO_MAPR_TIM5CH4_IREMAP AFIO_MAPR_TIM5CH4_IREMAP_Msk /* Set and cleared by software */
#define AFIO_MAPR_ADC1_ETRGINJ_REMAP_Pos (17U)
#define AFIO_MAPR_ADC1_ETRGINJ_REMAP_Msk (0x1U << AFIO_MAPR_ADC1_ETRGINJ_REMAP_Pos) /* 0x00020000 */
#define AFIO_MAPR_ADC1_ETRGINJ_REMAP AFIO_MAPR_ADC1_ETRGINJ_REMAP_Msk /* ADC 1 External trigger injected conversion remapping */
#define AFIO_MAPR_ADC1_ETRGREG_REMAP_Pos (18U)
#define AFIO_MAPR_ADC1_ETRGREG_REMAP_Msk (0x1U << AFIO_MAPR_ADC1_ETRGREG_REMAP_Pos) /* 0x00040000 */
#define AFIO_MAPR_ADC1_ETRGREG_REMAP AFIO_MAPR_ADC1_ETRGREG_REMAP_Msk /* ADC 1 external trigger regular conversion remapping */
#define AFIO_MAPR_ADC2_ETRGINJ_REMAP_Pos (19U)
#define AFIO_MAPR_ADC2_ETRGINJ_REMAP_Msk (0x1U << AFIO_MAPR_ADC2_ETRGINJ_REMAP_Pos) /* 0x00080000 */
#define AFIO_MAPR_ADC2_ETRGINJ_REMAP AFIO_MAPR_ADC2_ETRGINJ_REMAP_Msk /* ADC 2 external trigger injected conversion remapping */
#define AFIO_MAPR_ADC2_ETRGREG_REMAP_Pos (20U)
#define AFIO_MAPR_ADC2_ETRGREG_REMAP_Msk (0x1U << AFIO_MAPR_ADC2_ETRGREG_REMAP_Pos) /* 0x00100000 */
#define AFIO_MAPR_ADC2_ETRGREG_REMAP AFIO_MAPR_ADC2_ETRGREG_REMAP_Msk /* ADC 2 external trigger regular conversion remapping */
#define AFIO_MAPR_SWJ_CFG_Pos (24U)
#define AFIO_MAPR_SWJ_CFG_Msk (0x7U << AFIO_MAPR_SWJ_CFG_Pos) /* 0x07000000 */
#define AFIO_MAPR_SWJ_CFG AFIO_MAPR_SWJ_CFG_Msk /* Serial wire JTAG configuration */
#define AFIO_MAPR_SWJ_CFG_0 (0x1U << AFIO_MAPR_SWJ_CFG_Pos) /* 0x01000000 */
#define AFIO_MAPR_SWJ_CFG_1 (0x2U << AFIO_MAPR_SWJ_CFG_Pos) /* 0x02000000 */
#define AFIO_MAPR_SWJ_CFG_2 (0x4U << AFIO_MAPR_SWJ_CFG_Pos) /* 0x04000000 */

/* AFIO_EXTICR1 */
#define AFIO_EXTICR1_EXTI0_Pos (0U)
#define AFIO_EXTICR1_EXTI0_Msk (0xfU << AFIO_EXTICR1_EXTI0_Pos) /* 0x0000000F */
#define AFIO_EXTICR1_EXTI0 AFIO_EXTICR1_EXTI0_Msk /* EXTI0 configuration */
#define AFIO_EXTICR1_EXTI0_0 (0x1U << AFIO_EXTICR1_EXTI0_Pos) /* 0x00000001 */
#define AFIO_EXTICR1_EXTI0_1 (0x2U << AFIO_EXTICR1_EXTI0_Pos) /* 0x00000002 */
#define AFIO_EXTICR1_EXTI0_2 (0x4U << AFIO_EXTICR1_EXTI0_Pos) /* 0x00000004 */
#define AFIO_EXTICR1_EXTI0_3 (0x8U << AFIO_EXTICR1_EXTI0_Pos) /* 0x00000008 */
#define AFIO_EXTICR1_EXTI1_Pos (4U)
#define AFIO_EXTICR1_EXTI1_Msk (0xfU << AFIO_EXTICR1_EXTI1_Pos) /* 0x000000F0 */
#define AFIO_EXTICR1_EXTI1 AFIO_EXTICR1_EXTI1_Msk /* EXTI1 configuration */
#define AFIO_EXTICR1_EXTI1_0 (0x1U << AFIO_EXTICR1_EXTI1_Pos) /* 0x00000010 */
#define AFIO_EXTICR1_EXTI1_1 (0x2U << AFIO_EXTICR1_EXTI1_Pos) /* 0x00000020 */
#define AFIO_EXTICR1_EXTI1_2 (0x4U << AFIO_EXTICR1_EXTI1_Pos) /* 0x00000040 */
#define AFIO_EXTICR1_EXTI1_3 (0x8U << AFIO_EXTICR1_EXTI1_Pos) /* 0x00000080 */
#define AFIO_EXTICR1_EXTI2_Pos (8U)
#define AFIO_EXTICR1_EXTI2_Msk (0xfU << AFIO_EXTICR1_EXTI2_Pos) /* 0x00000F00 */
#define AFIO_EXTICR1_EXTI2 AFIO_EXTICR1_EXTI2_Msk /* EXTI2 configuration */
#define AFIO_EXTICR1_EXTI2_0 (0x1U << AFIO_EXTICR1_EXTI2_Pos) /* 0x00000100 */
#define AFIO_EXTICR1_EXTI2_1 (0x2U << AFIO_EXTICR1_EXTI2_Pos) /* 0x00000200 */
#define AFIO_EXTICR1_EXTI2_2 (0x4U << AFIO_EXTICR1_EXTI2_Pos) /* 0x00000400 */
#define AFIO_EXTICR1_EXTI2_3 (0x8U << AFIO_EXTICR1_EXTI2_Pos) /* 0x00000800 */
#define AFIO_EXTICR1_EXTI3_Pos (12U)
#define AFIO_EXTICR1_EXTI3_Msk (0xfU << AFIO_EXTICR1_EXTI3_Pos) /* 0x0000F000 */
#define AFIO_EXTICR1_EXTI3 AFIO_EXTICR1_EXTI3_Msk /* EXTI3 configuration */
#define AFIO_EXTICR1_EXTI3_0 (0x1U << AFIO_EXTICR1_EXTI3_Pos) /* 0x00001000 */
#define AFIO_EXTICR1_EXTI3_1 (0x2U << AFIO_EXTICR1_EXTI3_Pos) /* 0x00002000 */
#define AFIO_EXTICR1_EXTI3_2 (0x4U << AFIO_EXTICR1_EXTI3_Pos) /* 0x00004000 */
#define AFIO_EXTICR1_EXTI3_3 (0x8U << AFIO_EXTICR1_EXTI3_Pos) /* 0x00008000 */

/* AFIO_EXTICR2 */
#define AFIO_EXTICR2_EXTI4_Pos (0U)
#define AFIO_EXTICR2_EXTI4_Msk (0xfU << AFIO_EXTICR2_EXTI4_Pos) /* 0x0000000F */
#define AFIO_EXTICR2_EXTI4 AFIO_EXTICR2_EXTI4_Msk /* EXTI4 configuration */
#define AFIO_EXTICR2_EXTI4_0 (0x1U << AFIO_EXTICR2_EXTI4_Pos) /* 0x00000001 */
#define AFIO_EXTICR2_EXTI4_1 (0x2U << AFIO_EXTICR2_EXTI4_Pos) /* 0x00000002 */
#define AFIO_EXTICR2_EXTI4_2 (0x4U << AFIO_EXTICR2_EXTI4_Pos) /* 0x00000004 */
#define AFIO_EXTICR2_EXTI4_3 (0x8U << AFIO_EXTICR2_EXTI4_Pos) /* 0x00000008 */
#define AFIO_EXTICR2_EXTI5_Pos (4U)
#define AFIO_EXTICR2_EXTI5_Msk (0xfU << AFIO_EXTICR2_EXTI5_Pos) /* 0x000000F0 */
#define AFIO_EXTICR2_EXTI5 AFIO_EXTICR2_EXTI5_Msk /* EXTI5 configuration */
#define AFIO_EXTICR2_EXTI5_0 (0x1U << AFIO_EXTICR2_EXTI5_Pos) /* 0x00000010 */
#define AFIO_EXTICR2_EXTI5_1 (0x2U << AFIO_EXTICR2_EXTI5_Pos) /* 0x00000020 */
#define AFIO_EXTICR2_EXTI5_2 (0x4U << AFIO_EXTICR2_EXTI5_Pos) /* 0x00000040 */
#define AFIO_EXTICR2_EXTI5_3 (0x8U << AFIO_EXTICR2_EXTI5_Pos) /* 0x00000080 */
#define AFIO_EXTICR2_EXTI6_Pos (8U)
#define AFIO_EXTICR2_EXTI6_Msk (0xfU << AFIO_EXTICR2_EXTI6_Pos) /* 0x00000F00 */
#define AFIO_EXTICR2_EXTI6 AFIO_EXTICR2_EXTI6_Msk /* EXTI6 configuration */
#define AFIO_EXTICR2_EXTI6_0 (0x1U << AFIO_EXTICR2_EXTI6_Pos) /* 0x00000100 */
#define AFIO_EXTICR2_EXTI6_1 (0x2U << AFIO_EXTICR2_EXTI6_Pos) /* 0x00000200 */
#define AFIO_EXTICR2_EXTI6_2 (0x4U << AFIO_EXTICR2_EXTI6_Pos) /* 0x00000400 */
#define AFIO_EXTICR2_EXTI6_3 (0x8U << AFIO_EXTICR2_EXTI6_Pos) /* 0x00000800 */
#define AFIO_EXTICR2_EXTI7_Pos (12U)
#define AFIO_EXTICR2_EXTI7_Msk (0xfU << AFIO_EXTICR2_EXTI7_Pos) /* 0x0000F000 */
#define AFIO_EXTICR2_EXTI7 AFIO_EXTICR2_EXTI7_Msk /* EXTI7 configuration */
#define AFIO_EXTICR2_EXTI7_0 (0x1U << AFIO_EXTICR2_EXTI7_Pos) /* 0x00001000 */
#define AFIO_EXTICR2_EXTI7_1 (0x2U << AFIO_EXTICR2_EXTI7_Pos) /* 0x00002000 */
#define AFIO_EXTICR2_EXTI7_2 (0x4U << AFIO_EXTICR2_EXTI7_Pos) /* 0x00004000 */
#define AFIO_EXTICR2_EXTI7_3 (0x8U << AFIO_EXTICR2_EXTI7_Pos) /* 0x00008000 */

/* EXTI_IMR */
#define EXTI_IMR_MR0_Pos (0U)
#define EXTI_IMR_MR0_Msk (0x1U << EXTI_IMR_MR0_Pos) /* 0x00000001 */
#define EXTI_IMR_MR0 EXTI_IMR_MR0_Msk /* Interrupt Mask on line 0 */
#define EXTI_IMR_MR1_Pos (1U)
#define EXTI_IMR_MR1_Msk (0x1U << EXTI_IMR_MR1_Pos) /* 0x00000002 */
#define EXTI_IMR_MR1 EXTI_IMR_MR1_Msk /* Interrupt Mask on line 1 */
#define EXTI_IMR_MR2_Pos (2U)
#define EXTI_IMR_MR2_Msk (0x1U << EXTI_IMR_MR2_Pos) /* 0x00000004 */
#define EXTI_IMR_MR2 EXTI_IMR_MR2_Msk /* Interrupt Mask on line 2 */
#define EXTI_IMR_MR3_Pos (3U)
#define EXTI_IMR_MR3_Msk (0x1U << EXTI_IMR_MR3_Pos) /* 0x00000008 */
#define EXTI_IMR_MR3 EXTI_IMR_MR3_Msk /* Interrupt Mask on line 3 */
#define EXTI_IMR_MR4_Pos (4U)
#define EXTI_IMR_MR4_Msk (0x1U << EXTI_IMR_MR4_Pos) /* 0x00000010 */
#define EXTI_IMR_MR4 EXTI_IMR_MR4_Msk /* Interrupt Mask on line 4 */
#define EXTI_IMR_MR5_Pos (5U)
#define EXTI_IMR_MR5_Msk (0x1U << EXTI_IMR_MR5_Pos) /* 0x00000020 */
#define EXTI_IMR_MR5 EXTI_IMR_MR5_Msk /* Interrupt Mask on line 5 */
#define EXTI_IMR_MR6_Pos (6U)
#define EXTI_IMR_MR6_Msk (0x1U << EXTI_IMR_MR6_Pos) /* 0x00000040 */
#define EXTI_IMR_MR6 EXTI_IMR_MR6_Msk /* Interrupt Mask on line 6 */
#define EXTI_IMR_MR7_Pos (7U)
#define EXTI_IMR_MR7_Msk (0x1U << EXTI_IMR_MR7_Pos) /* 0x00000080 */
#define EXTI_IMR_MR7 EXTI_IMR_MR7_Msk /* Interrupt Mask on line 7 */
#define EXTI_IMR_MR8_Pos (8U)
#define EXTI_IMR_MR8_Msk (0x1U << EXTI_IMR_MR8_Pos) /* 0x00000100 */
#define EXTI_IMR_MR8 EXTI_IMR_MR8_Msk /* Interrupt Mask on line 8 */
#define EXTI_IMR_MR9_Pos (9U)
#define EXTI_IMR_MR9_Msk (0x1U << EXTI_IMR_MR9_Pos) /* 0x00000200 */
#define EXTI_IMR_MR9 EXTI_IMR_MR9_Msk /* Interrupt Mask on line 9 */
#define EXTI_IMR_MR10_Pos (10U)
#define EXTI_IMR_MR10_Msk (0x1U << EXTI_IMR_MR10_Pos) /* 0x00000400 */
#define EXTI_IMR_MR10 EXTI_IMR_MR10_Msk /* Interrupt Mask on line 10 */
#define EXTI_IMR_MR11_Pos (11U)
#define EXTI_IMR_MR11_Msk (0x1U << EXTI_IMR_MR11_Pos) /* 0x00000800 */
#define EXTI_IMR_MR11 EXTI_IMR_MR11_Msk /* Interrupt Mask on line 11 */
#define EXTI_IMR_MR12_Pos (12U)
#define EXTI_IMR_MR12_Msk (0x1U << EXTI_IMR_MR12_Pos) /* 0x00001000 */
#define EXTI_IMR_MR12 EXTI_IMR_MR12_Msk /* Interrupt Mask on line 12 */
#define EXTI_IMR_MR13_Pos (13U)
#define EXTI_IMR_MR13_Msk (0x1U << EXTI_IMR_MR13_Pos) /* 0x00002000 */
#define EXTI_IMR_MR13 EXTI_IMR_MR13_Msk /* Interrupt Mask on line 13 */
#define EXTI_IMR_MR14_Pos (14U)
#define EXTI_IMR_MR14_Msk (0x1U << EXTI_IMR_MR14_Pos) /* 0x00004000 */
#define EXTI_IMR_MR14 EXTI_IMR_MR14_Msk /* Interrupt Mask on line 14 */
#define EXTI_IMR_MR15_Pos (15U)
#define EXTI_IMR_MR15_Msk (0x1U << EXTI_IMR_MR15_Pos) /* 0x00008000 */
#define EXTI_IMR_MR15 EXTI_IMR_MR15_Msk /* Interrupt Mask on line 15 */
#define EXTI_IMR_MR16_Pos (16U)
#define EXTI_IMR_MR16_Msk (0x1U << EXTI_IMR_MR16_Pos) /* 0x00010000 */
#define EXTI_IMR_MR16 EXTI_IMR_MR16_Msk /* Interrupt Mask on line 16 */
#define EXTI_IMR_MR17_Pos (17U)
#define EXTI_IMR_MR17_Msk (0x1U << EXTI_IMR_MR17_Pos) /* 0x00020000 */
#define EXTI_IMR_MR17 EXTI_IMR_MR17_Msk /* Interrupt Mask on line 17 */
#define EXTI_IMR_MR18_Pos (18U)
#define EXTI_IMR_MR18_Msk (0x1U << EXTI_IMR_MR18_Pos) /* 0x00040000 */
#define EXTI_IMR_MR18 EXTI_IMR_MR18_Msk /* Interrupt Mask on line 18 */

/* EXTI_RTSR */
#define EXTI_RTSR_TR0_Pos (0U)
#define EXTI_RTSR_TR0_Msk (0x1U << EXTI_RTSR_TR0_Pos) /* 0x00000001 */
#define EXTI_RTSR_TR0 EXTI_RTSR_TR0_Msk /* Rising trigger event configuration of line 0 */
#define EXTI_RTSR_TR1_Pos (1U)
#define EXTI_RTSR_TR1_Msk (0x1U << EXTI_RTSR_TR1_Pos) /* 0x00000002 */
#define EXTI_RTSR_TR1 EXTI_RTSR_TR1_Msk /* Rising trigger event configuration of line 1 */
#define EXTI_RTSR_TR2_Pos (2U)
#define EXTI_RTSR_TR2_Msk (0x1U << EXTI_RTSR_TR2_Pos) /* 0x00000004 */
#define EXTI_RTSR_TR2 EXTI_RTSR_TR2_Msk /* Rising trigger event configuration of line 2 */
#define EXTI_RTSR_TR3_Pos (3U)
#define EXTI_RTSR_TR3_Msk (0x1U << EXTI_RTSR_TR3_Pos) /* 0x00000008 */
#define EXTI_RTSR_TR3 EXTI_RTSR_TR3_Msk /* Rising trigger event configuration of line 3 */
#define EXTI_RTSR_TR4_Pos (4U)
#define EXTI_RTSR_TR4_Msk (0x1U << EXTI_RTSR_TR4_Pos) /* 0x00000010 */
#define EXTI_RTSR_TR4 EXTI_RTSR_TR4_Msk /* Rising trigger event configuration of line 4 */
#define EXTI_RTSR_TR5_Pos (5U)
#define EXTI_RTSR_TR5_Msk (0x1U << EXTI_RTSR_TR5_Pos) /* 0x00000020 */
#define EXTI_RTSR_TR5 EXTI_RTSR_TR5_Msk /* Rising trigger event configuration of line 5 */
#define EXTI_RTSR_TR6_Pos (6U)
#define EXTI_RTSR_TR6_Msk (0x1U << EXTI_RTSR_TR6_Pos) /* 0x00000040 */
#define EXTI_RTSR_TR6 EXTI_RTSR_TR6_Msk /* Rising trigger event configuration of line 6 */
#define EXTI_RTSR_TR7_Pos (7U)
#define EXTI_RTSR_TR7_Msk (0x1U << EXTI_RTSR_TR7_Pos) /* 0x00000080 */
#define EXTI_RTSR_TR7 EXTI_RTSR_TR7_Msk /* Rising trigger event configuration of line 7 */
#define EXTI_RTSR_TR8_Pos (8U)
#define EXTI_RTSR_TR8_Msk (0x1U << EXTI_RTSR_TR8_Pos) /* 0x00000100 */
#define EXTI_RTSR_TR8 EXTI_RTSR_TR8_Msk /* Rising trigger event configuration of line 8 */
#define EXTI_RTSR_TR9_Pos (9U)
#define EXTI_RTSR_TR9_Msk (0x1U << EXTI_RTSR_TR9_Pos) /* 0x00000200 */
#define EXTI_RTSR_TR9 EXTI_RTSR_TR9_Msk /* Rising trigger event configuration of line 9 */
#define EXTI_RTSR_TR10_Pos (10U)
#define EXTI_RTSR_TR10_Msk (0x1U << EXTI_RTSR_TR10_Pos) /* 0x00000400 */
#define EXTI_RTSR_TR10 EXTI_RTSR_TR10_Msk /* Rising trigger event configuration of line 10 */
#define EXTI_RTSR_TR11_Pos (11U)
#define EXTI_RTSR_TR11_Msk (0x1U << EXTI_RTSR_TR11_Pos) /* 0x00000800 */
#define EXTI_RTSR_TR11 EXTI_RTSR_TR11_Msk /* Rising trigger event configuration of line 11 */
#define EXTI_RTSR_TR12_Pos (12U)
#define EXTI_RTSR_TR12_Msk (0x1U << EXTI_RTSR_TR12_Pos) /* 0x00001000 */
#define EXTI_RTSR_TR12 EXTI_RTSR_TR12_Msk /* Rising trigger event configuration of line 12 */
#define EXTI_RTSR_TR13_Pos (13U)
#define EXTI_RTSR_TR13_Msk (0x1U << EXTI_RTSR_TR13_Pos) /* 0x00002000 */
#define EXTI_RTSR_TR13 EXTI_RTSR_TR13_Msk /* Rising trigger event configuration of line 13 */
#define EXTI_RTSR_TR14_Pos (14U)
#define EXTI_RTSR_TR14_Msk (0x1U << EXTI_RTSR_TR14_Pos) /* 0x00004000 */
#define EXTI_RTSR_TR14 EXTI_RTSR_TR14_Msk /* Rising trigger event configuration of line 14 */
#define EXTI_RTSR_TR15_Pos (15U)
#define EXTI_RTSR_TR15_Msk (0x1U << EXTI_RTSR_TR15_Pos) /* 0x00008000 */
#define EXTI_RTSR_TR15 EXTI_RTSR_TR15_Msk /* Rising trigger event configuration of line 15 */
#define EXTI_RTSR_TR16_Pos (16U)
#define EXTI_RTSR_TR16_Msk (0x1U << EXTI_RTSR_TR16_Pos) /* 0x00010000 */
#define EXTI_RTSR_TR16 EXTI_RTSR_TR16_Msk /* Rising trigger event configuration of line 16 */
#define EXTI_RTSR_TR17_Pos (17U)
#define EXTI_RTSR_TR17_Msk (0x1U << EXTI_RTSR_TR17_Pos) /* 0x00020000 */
#define EXTI_RTSR_TR17 EXTI_RTSR_TR17_Msk /* Rising trigger event configuration of line 17 */
#define EXTI_RTSR_TR18_Pos (18U)
#define EXTI_RTSR_TR18_Msk (0x1U << EXTI_RTSR_TR18_Pos) /* 0x00040000 */
#define EXTI_RTSR_TR18 EXTI_RTSR_TR18_Msk /* Rising trigger event configuration of line 18 */

/* EXTI_FTSR */
#define EXTI_FTSR_TR0_Pos (0U)
#define EXTI_FTSR_TR0_Msk (0x1U << EXTI_FTSR_TR0_Pos) /* 0x00000001 */
#define EXTI_FTSR_TR0 EXTI_FTSR_TR0_Msk /* Falling trigger event configuration of line 0 */
#define EXTI_FTSR_TR1_Pos (1U)
#define EXTI_FTSR_TR1_Msk (0x1U << EXTI_FTSR_TR1_Pos) /* 0x00000002 */
#define EXTI_FTSR_TR1 EXTI_FTSR_TR1_Msk /* Falling trigger event configuration of line 1 */
#define EXTI_FTSR_TR2_Pos (2U)
#define EXTI_FTSR_TR2_Msk (0x1U << EXTI_FTSR_TR2_Pos) /* 0x00000004 */
#define EXTI_FTSR_TR2 EXTI_FTSR_TR2_Msk /* Falling trigger event configuration of line 2 */
#define EXTI_FTSR_TR3_Pos (3U)
#define EXTI_FTSR_TR3_Msk (0x1U << EXTI_FTSR_TR3_Pos) /* 0x00000008 */
#define EXTI_FTSR_TR3 EXTI_FTSR_TR3_Msk /* Falling trigger event configuration of line 3 */
#define EXTI_FTSR_TR4_Pos (4U)
#define EXTI_FTSR_TR4_Msk (0x1U << EXTI_FTSR_TR4_Pos) /* 0x00000010 */
#define EXTI_FTSR_TR4 EXTI_FTSR_TR4_Msk /* Falling trigger event configuration of line 4 */
#define EXTI_FTSR_TR5_Pos (5U)
#define EXTI_FTSR_TR5_Msk (0x1U << EXTI_FTSR_TR5_Pos) /* 0x00000020 */
#define EXTI_FTSR_TR5 EXTI_FTSR_TR5_Msk /* Falling trigger event configuration of line 5 */
#define EXTI_FTSR_TR6_Pos (6U)
#define EXTI_FTSR_TR6_Msk (0x1U << EXTI_FTSR_TR6_Pos) /* 0x00000040 */
#define EXTI_FTSR_TR6 EXTI_FTSR_TR6_Msk /* Falling trigger event configuration of line 6 */
#define EXTI_FTSR_TR7_Pos (7U)
#define EXTI_FTSR_TR7_Msk (0x1U << EXTI_FTSR_TR7_Pos) /* 0x00000080 */
#define EXTI_FTSR_TR7 EXTI_FTSR_TR7_Msk /* Falling trigger event configuration of line 7 */
#define EXTI_FTSR_TR8_Pos (8U)
#define EXTI_FTSR_TR8_Msk (0x1U << EXTI_FTSR_TR8_Pos) /* 0x00000100 */
#define EXTI_FTSR_TR8 EXTI_FTSR_TR8_Msk /* Falling trigger event configuration of line 8 */
#define EXTI_FTSR_TR9_Pos (9U)
#define EXTI_FTSR_TR9_Msk (0x1U << EXTI_FTSR_TR9_Pos) /* 0x00000200 */
#define EXTI_FTSR_TR9 EXTI_FTSR_TR9_Msk /* Falling trigger event configuration of line 9 */
#define EXTI_FTSR_TR10_Pos (10U)
#define EXTI_FTSR_TR10_Msk (0x1U << EXTI_FTSR_TR10_Pos) /* 0x00000400 */
#define EXTI_FTSR_TR10 EXTI_FTSR_TR10_Msk /* Falling trigger event configuration of line 10 */
#define EXTI_FTSR_TR11_Pos (11U)
#define EXTI_FTSR_TR11_Msk (0x1U << EXTI_FTSR_TR11_Pos) /* 0x00000800 */
#define EXTI_FTSR_TR11 EXTI_FTSR_TR11_Msk /* Falling trigger event configuration of line 11 */
#define EXTI_FTSR_TR12_Pos (12U)
#define EXTI_FTSR_TR12_Msk (0x1U << EXTI_FTSR_TR12_Pos) /* 0x00001000 */
#define EXTI_FTSR_TR12 EXTI_FTSR_TR12_Msk /* Falling trigger event configuration of line 12 */
#define EXTI_FTSR_TR13_Pos (13U)
#define EXTI_FTSR_TR13_Msk (0x1U << EXTI_FTSR_TR13_Pos) /* 0x00002000 */
#define EXTI_FTSR_TR13 EXTI_FTSR_TR13_Msk /* Falling trigger event configuration of line 13 */
#define EXTI_FTSR_TR14_Pos (14U)
#define EXTI_FTSR_TR14_Msk (0x1U << EXTI_FTSR_TR14_Pos) /* 0x00004000 */
#define EXTI_FTSR_TR14 EXTI_FTSR_TR14_Msk /* Falling trigger event configuration of line 14 */
#define EXTI_FTSR_TR15_Pos (15U)
#define EXTI_FTSR_TR15_Msk (0x1U << EXTI_FTSR_TR15_Pos) /* 0x00008000 */
#define EXTI_FTSR_TR15 EXTI_FTSR_TR15_Msk /* Falling trigger event configuration of line 15 */
#define EXTI_FTSR_TR16_Pos (16U)
#define EXTI_FTSR_TR16_Msk (0x1U << EXTI_FTSR_TR16_Pos) /* 0x00010000 */
#define EXTI_FTSR_TR16 EXTI_FTSR_TR16_Msk /* Falling trigger event configuration of line 16 */
#define EXTI_FTSR_TR17_Pos (17U)
#define EXTI_FTSR_TR17_Msk (0x1U << EXTI_FTSR_TR17_Pos) /* 0x00020000 */
#define EXTI_FTSR_TR17 EXTI_FTSR_TR17_Msk /* Falling trigger event configuration of line 17 */
#define EXTI_FTSR_TR18_Pos (18U)
#define EXTI_FTSR_TR18_Msk (0x1U << EXTI_FTSR_TR18_Pos) /* 0x00040000 */
#define EXTI_FTSR_TR18 EXTI_FTSR_TR18_Msk /* Falling trigger event configuration of line 18 */

/* EXTI_SWIER */
#define EXTI_SWIER_SWIER0_Pos (0U)
#define EXTI_SWIER_SWIER0_Msk (0x1U << EXTI_SWIER_SWIER0_Pos) /* 0x00000001 */
#define EXTI_SWIER_SWIER0 EXTI_SWIER_SWIER0_Msk /* Software Interrupt on line 0 */
#define EXTI_SWIER_SWIER1_Pos (1U)
#define EXTI_SWIER_SWIER1_Msk (0x1U << EXTI_SWIER_SWIER1_Pos) /* 0x00000002 */
#define EXTI_SWIER_SWIER1 EXTI_SWIER_SWIER1_Msk /* Software Interrupt on line 1 */
#define EXTI_SWIER_SWIER2_Pos (2U)
#define EXTI_SWIER_SWIER2_Msk (0x1U << EXTI_SWIER_SWIER2_Pos) /* 0x00000004 */
#define EXTI_SWIER_SWIER2 EXTI_SWIER_SWIER2_Msk /* Software Interrupt on line 2 */
#define EXTI_SWIER_SWIER3_Pos (3U)
#define EXTI_SWIER_SWIER3_Msk (0x1U << EXTI_SWIER_SWIER3_Pos) /* 0x00000008 */
#define EXTI_SWIER_SWIER3 EXTI_SWIER_SWIER3_Msk /* Software Interrupt on line 3 */
#define EXTI_SWIER_SWIER4_Pos (4U)
#define EXTI_SWIER_SWIER4_Msk (0x1U << EXTI_SWIER_SWIER4_Pos) /* 0x00000010 */
#define EXTI_SWIER_SWIER4 EXTI_SWIER_SWIER4_Msk /* Software Interrupt on line 4 */
#define EXTI_SWIER_SWIER5_Pos (5U)
#define EXTI_SWIER_SWIER5_Msk (0x1U << EXTI_SWIER_SWIER5_Pos) /* 0x00000020 */
#define EXTI_SWIER_SWIER5 EXTI_SWIER_SWIER5_Msk /* Software Interrupt on line 5 */
#define EXTI_SWIER_SWIER6_Pos (6U)
#define EXTI_SWIER_SWIER6_Msk (0x1U << EXTI_SWIER_SWIER6_Pos) /* 0x00000040 */
#define EXTI_SWIER_SWIER6 EXTI_SWIER_SWIER6_Msk /* Software Interrupt on line 6 */
#define EXTI_SWIER_SWIER7_Pos (7U)
#define EXTI_SWIER_SWIER7_Msk (0x1U << EXTI_SWIER_SWIER7_Pos) /* 0x00000080 */
#define EXTI_SWIER_SWIER7 EXTI_SWIER_SWIER7_Msk /* Software Interrupt on line 7 */
#define EXTI_SWIER_SWIER8_Pos (8U)
#define EXTI_SWIER_SWIER8_Msk (0x1U << EXTI_SWIER_SWIER8_Pos) /* 0x00000100 */
#define EXTI_SWIER_SWIER8 EXTI_SWIER_SWIER8_Msk /* Software Interrupt on line 8 */
#define EXTI_SWIER_SWIER9_Pos (9U)
#define EXTI_SWIER_SWIER9_Msk (0x1U << EXTI_SWIER_SWIER9_Pos) /* 0x00000200 */
#define EXTI_SWIER_SWIER9 EXTI_SWIER_SWIER9_Msk /* Software Interrupt on line 9 */
#define EXTI_SWIER_SWIER10_Pos (10U)
#define EXTI_SWIER_SWIER10_Msk (0x1U << EXTI_SWIER_SWIER10_Pos) /* 0x00000400 */
#define EXTI_SWIER_SWIER10 EXTI_SWIER_SWIER10_Msk /* Software Interrupt on line 10 */
#define EXTI_SWIER_SWIER11_Pos (11U)
#define EXTI_SWIER_SWIER11_Msk (0x1U << EXTI_SWIER_SWIER11_Pos) /* 0x00000800 */
#define EXTI_SWIER_SWIER11 EXTI_SWIER_SWIER11_Msk /* Software Interrupt on line 11 */
#define EXTI_SWIER_SWIER12_Pos (12U)
#define EXTI_SWIER_SWIER12_Msk (0x1U << EXTI_SWIER_SWIER12_Pos) /* 0x00001000 */
#define EXTI_SWIER_SWIER12 EXTI_SWIER_SWIER12_Msk /* Software Interrupt on line 12 */
#define EXTI_SWIER_SWIER13_Pos (13U)
#define EXTI_SWIER_SWIER13_Msk (0x1U << EXTI_SWIER_SWIER13_Pos) /* 0x00002000 */
#define EXTI_SWIER_SWIER13 EXTI_SWIER_SWIER13_Msk /* Software Interrupt on line 13 */
#define EXTI_SWIER_SWIER14_Pos (14U)
#define EXTI_SWIER_SWIER14_Msk (0x1U << EXTI_SWIER_SWIER14_Pos) /* 0x00004000 */
#define EXTI_SWIER_SWIER14 EXTI_SWIER_SWIER14_Msk /* Software Interrupt on line 14 */
#define EXTI_SWIER_SWIER15_Pos (15U)
#define EXTI_SWIER_SWIER15_Msk (0x1U << EXTI_SWIER_SWIER15_Pos) /* 0x00008000 */
#define EXTI_SWIER_SWIER15 EXTI_SWIER_SWIER15_Msk /* Software Interrupt on line 15 */
#define EXTI_SWIER_SWIER16_Pos (16U)
#define EXTI_SWIER_SWIER16_Msk (0x1U << EXTI_SWIER_SWIER16_Pos) /* 0x00010000 */
#define EXTI_SWIER_SWIER16 EXTI_SWIER_SWIER16_Msk /* Software Interrupt on line 16 */
#define EXTI_SWIER_SWIER17_Pos (17U)
#define EXTI_SWIER_SWIER17_Msk (0x1U << EXTI_SWIER_SWIER17_Pos) /* 0x00020000 */
#define EXTI_SWIER_SWIER17 EXTI_SWIER_SWIER17_Msk /* Software Interrupt on line 17 */
#define EXTI_SWIER_SWIER18_Pos (18U)
#define EXTI_SWIER_SWIER18_Msk (0x1U << EXTI_SWIER_SWIER18_Pos) /* 0x00040000 */
#define EXTI_SWIER_SWIER18 EXTI_SWIER_SWIER18_Msk /* Software Interrupt on line 18 */

/* EXTI_PR */
#define EXTI_PR_PR0_Pos (0U)
#define EXTI_PR_PR0_Msk (0x1U << EXTI_PR_PR0_Pos) /* 0x00000001 */
#define EXTI_PR_PR0 EXTI_PR_PR0_Msk /* Pending bit 0 */
#define EXTI_PR_PR1_Pos (1U)
#define EXTI_PR_PR1_Msk (0x1U << EXTI_PR_PR1_Pos) /* 0x00000002 */
#define EXTI_PR_PR1 EXTI_PR_PR1_Msk /* Pending bit 1 */
#define EXTI_PR_PR2_Pos (2U)
#define EXTI_PR_PR2_Msk (0x1U << EXTI_PR_PR2_Pos) /* 0x00000004 */
#define EXTI_PR_PR2 EXTI_PR_PR2_Msk /* Pending bit 2 */
#define EXTI_PR_PR3_Pos (3U)
#define EXTI_PR_PR3_Msk (0x1U << EXTI_PR_PR3_Pos) /* 0x00000008 */
#define EXTI_PR_PR3 EXTI_PR_PR3_Msk /* Pending bit 3 */
#define EXTI_PR_PR4_Pos (4U)
#define EXTI_PR_PR4_Msk (0x1U << EXTI_PR_PR4_Pos) /* 0x00000010 */
#define EXTI_PR_PR4 EXTI_PR_PR4_Msk /* Pending bit 4 */
#define EXTI_PR_PR5_Pos (5U)
#define EXTI_PR_PR5_Msk (0x1U << EXTI_PR_PR5_Pos) /* 0x00000020 */
#define EXTI_PR_PR5 EXTI_PR_PR5_Msk /* Pending bit 5 */
#define EXTI_PR_PR6_Pos (6U)
#define EXTI_PR_PR6_Msk (0x1U << EXTI_PR_PR6_Pos) /* 0x00000040 */
#define EXTI_PR_PR6 EXTI_PR_PR6_Msk /* Pending bit 6 */
#define EXTI_PR_PR7_Pos (7U)
#define EXTI_PR_PR7_Msk (0x1U << EXTI_PR_PR7_Pos) /* 0x00000080 */
#define EXTI_PR_PR7 EXTI_PR_PR7_Msk /* Pending bit 7 */
#define EXTI_PR_PR8_Pos (8U)
#define EXTI_PR_PR8_Msk (0x1U << EXTI_PR_PR8_Pos) /* 0x00000100 */
#define EXTI_PR_PR8 EXTI_PR_PR8_Msk /* Pending bit 8 */
#define EXTI_PR_PR9_Pos (9U)
#define EXTI_PR_PR9_Msk (0x1U << EXTI_PR_PR9_Pos) /* 0x00000200 */
#define EXTI_PR_PR9 EXTI_PR_PR9_Msk /* Pending bit 9 */
#define EXTI_PR_PR10_Pos (10U)
#define EXTI_PR_PR10_Msk (0x1U << EXTI_PR_PR10_Pos) /* 0x00000400 */
#define EXTI_PR_PR10 EXTI_PR_PR10_Msk /* Pending bit 10 */
#define EXTI_PR_PR11_Pos (11U)
#define EXTI_PR_PR11_Msk (0x1U << EXTI_PR_PR11_Pos) /* 0x00000800 */
#define EXTI_PR_PR11 EXTI_PR_PR11_Msk /* Pending bit 11 */
#define EXTI_PR_PR12_Pos (12U)
#define EXTI_PR_PR12_Msk (0x1U << EXTI_PR_PR12_Pos) /* 0x00001000 */
#define EXTI_PR_PR12 EXTI_PR_PR12_Msk /* Pending bit 12 */
#define EXTI_PR_PR13_Pos (13U)
#define EXTI_PR_PR13_Msk (0x1U << EXTI_PR_PR13_Pos) /* 0x00002000 */
#define EXTI_PR_PR13 EXTI_PR_PR13_Msk /* Pending bit 13 */
#define EXTI_PR_PR14_Pos (14U)
#define EXTI_PR_PR14_Msk (0x1U << EXTI_PR_PR14_Pos) /* 0x00004000 */
#define EXTI_PR_PR14 EXTI_PR_PR14_Msk /* Pending bit 14 */
#define EXTI_PR_PR15_Pos (15U)
#define EXTI_PR_PR15_Msk (0x1U << EXTI_PR_PR15_Pos) /* 0x00008000 */
#define EXTI_PR_PR15 EXTI_PR_PR15_Msk /* Pending bit 15 */
#define EXTI_PR_PR16_Pos (16U)
#define EXTI_PR_PR16_Msk (0x1U << EXTI_PR_PR16_Pos) /* 0x00010000 */
#define EXTI_PR_PR16 EXTI_PR_PR16_Msk /* Pending bit 16 */
#define EXTI_PR_PR17_Pos (17U)
#define EXTI_PR_PR17_Msk (0x1U << EXTI_PR_PR17_Pos) /* 0x00020000 */
#define EXTI_PR_PR17 EXTI_PR_PR17_Msk /* Pending bit 17 */
#define EXTI_PR_PR18_Pos (18U)
#define EXTI_PR_PR18_Msk (0x1U << EXTI_PR_PR18_Pos) /* 0x00040000 */
#define EXTI_PR_PR18 EXTI_PR_PR18_Msk /* Pending bit 18 */

/* NVIC interrupt set-enable registers (ARMv7-M ARM B3.4.4: NVIC_ISER0..n, one bit per
 * interrupt, 32 interrupts per register; writing 0 bits has no effect). */
#define NVIC_ISER_BASE 0xE000E100UL /* SVD NVIC.ISER0: Interrupt Set-Enable Register */

/* NVIC interrupt set-pending registers (B3.4.6: NVIC_ISPR0..n, same layout) and
 * priority registers (B3.4.9: NVIC_IPR0..n, one byte per interrupt, byte-accessible). */
#define NVIC_ISPR_BASE 0xE000E200UL /* SVD NVIC.ISPR0: Interrupt Set-Pending Register */
#define NVIC_IPR_BASE 0xE000E400UL /* SVD NVIC.IPR0: Interrupt Priority Register */
/* Interrupt clear-pending registers (B3.4.7: NVIC_ICPR0..n, same layout). */
#define NVIC_ICPR_BASE 0xE000E280UL /* SVD NVIC.ICPR0: Interrupt Clear-Pending Register */

/* Implemented priority bits: the STM32F10x has 16 levels in the upper nibble of each
 * priority byte (PM0056 4.3.7; Cube's stm32f103xb.h: __NVIC_PRIO_BITS 4). */
#define __NVIC_PRIO_BITS 4U

/* CMSIS core_cm3.h's NVIC_EnableIRQ, NVIC_SetPendingIRQ, NVIC_ClearPendingIRQ and
 * NVIC_SetPriority for device interrupts (IRQn >= 0). */
static inline void NVIC_EnableIRQ(IRQn_Type IRQn)
{
    volatile uint32_t *const iser = (volatile uint32_t *)NVIC_ISER_BASE;
    iser[((uint32_t)IRQn) >> 5U] = (uint32_t)(1U << (((uint32_t)IRQn) & 0x1FU));
}

static inline void NVIC_SetPendingIRQ(IRQn_Type IRQn)
{
    volatile uint32_t *const ispr = (volatile uint32_t *)NVIC_ISPR_BASE;
    ispr[((uint32_t)IRQn) >> 5U] = (uint32_t)(1U << (((uint32_t)IRQn) & 0x1FU));
}

static inline void NVIC_ClearPendingIRQ(IRQn_Type IRQn)
{
    volatile uint32_t *const icpr = (volatile uint32_t *)NVIC_ICPR_BASE;
    icpr[((uint32_t)IRQn) >> 5U] = (uint32_t)(1U << (((uint32_t)IRQn) & 0x1FU));
}

static inline void NVIC_SetPriority(IRQn_Type IRQn, uint32_t priority)
{
    volatile uint8_t *const ipr = (volatile uint8_t *)NVIC_IPR_BASE;
    ipr[(uint32_t)IRQn] = (uint8_t)((priority << (8U - __NVIC_PRIO_BITS)) & 0xFFU);
}

/* The SysTick timer: a core peripheral the vendor SVD does not describe (codegen/svd.py
 * CORE_PERIPHERALS, from the ARMv7-M Architecture Reference Manual), with CMSIS
 * core_cm3.h's names. */
typedef struct {
    __IO uint32_t CTRL;  /* SYST_CSR, offset 0x00 */
    __IO uint32_t LOAD;  /* SYST_RVR, offset 0x04 */
    __IO uint32_t VAL;   /* SYST_CVR, offset 0x08 */
    __I uint32_t CALIB;  /* SYST_CALIB, offset 0x0C */
} SysTick_Type;
#define SysTick_BASE 0xE000E010UL /* ARMv7-M ARM B3.3.2 SYST_CSR (not in the vendor SVD) */
#define SysTick ((SysTick_Type *)SysTick_BASE)
#define SysTick_CTRL_ENABLE_Msk (1UL << 0U) /* counter enabled */
#define SysTick_CTRL_CLKSOURCE_Msk (1UL << 2U) /* counts the processor clock */
#define SysTick_CTRL_COUNTFLAG_Msk (1UL << 16U) /* wrapped since the last read (the read clears it) */

/* The cycle counter: the DWT and CoreDebug core peripherals, not in the vendor SVD either
 * (codegen/svd.py CYCLE_COUNTER_BITS, from the ARMv7-M Architecture Reference Manual), with
 * CMSIS core_cm3.h's names; only the registers the port uses. */
typedef struct {
    __IO uint32_t CTRL;   /* DWT_CTRL, offset 0x00 */
    __IO uint32_t CYCCNT; /* DWT_CYCCNT, offset 0x04 */
} DWT_Type;
#define DWT_BASE 0xE0001000UL /* ARMv7-M ARM C1.8.7 DWT_CTRL (not in the vendor SVD) */
#define DWT ((DWT_Type *)DWT_BASE)
typedef struct {
    __IO uint32_t DHCSR; /* offset 0x00 */
    __IO uint32_t DCRSR; /* offset 0x04 */
    __IO uint32_t DCRDR; /* offset 0x08 */
    __IO uint32_t DEMCR; /* offset 0x0C */
} CoreDebug_Type;
#define CoreDebug_BASE 0xE000EDF0UL /* ARMv7-M ARM C1.6 DHCSR (not in the vendor SVD) */
#define CoreDebug ((CoreDebug_Type *)CoreDebug_BASE)
#define DWT_CTRL_CYCCNTENA_Msk (1UL << 0U) /* DWT_CTRL: CYCCNT counts the processor clock */
#define CoreDebug_DEMCR_TRCENA_Msk (1UL << 24U) /* DEMCR: the DWT and ITM enabled */

/* CMSIS cmsis_gcc.h's PRIMASK intrinsics. A host build (the project's tests) has no
 * interrupts to mask, so there they do nothing. */
#if defined(__arm__)
static inline uint32_t __get_PRIMASK(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask" : "=r"(primask));
    return primask;
}

static inline void __set_PRIMASK(uint32_t primask)
{
    __asm__ volatile("msr primask, %0" : : "r"(primask) : "memory");
}

static inline void __disable_irq(void)
{
    __asm__ volatile("cpsid i" : : : "memory");
}
#else
static inline uint32_t __get_PRIMASK(void)
{
    return 0U;
}

static inline void __set_PRIMASK(uint32_t primask)
{
    (void)primask;
}

static inline void __disable_irq(void)
{
}
#endif

#endif /* USE_CMSIS_DEVICE_HEADER */

#endif /* STM32F103_REGS_H */
